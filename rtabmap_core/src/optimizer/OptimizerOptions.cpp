#include <cmath>
#include <sstream>

#include "rtabmap_core/optimizer/Optimizer.h"

namespace rtabmap {

const char* initializationName(GraphInitialization init) {
  switch (init) {
    case GraphInitialization::kInputPoses: return "input";
    case GraphInitialization::kSpanningTree: return "tree";
    case GraphInitialization::kChordal: return "chordal";
  }
  return "unknown";
}

std::optional<GraphInitialization> initializationFromName(const std::string& name) {
  if (name == "input" || name == "odometry") return GraphInitialization::kInputPoses;
  if (name == "tree") return GraphInitialization::kSpanningTree;
  if (name == "chordal") return GraphInitialization::kChordal;
  return std::nullopt;
}

OptimizerOptions OptimizerOptions::fromParameters(const ParametersMap& parameters) {
  OptimizerOptions o;
  o.iterations = Parameters::getInt(parameters, Parameters::kOptimizerIterations());
  o.epsilon = Parameters::getDouble(parameters, Parameters::kOptimizerEpsilon());
  o.initialization =
      static_cast<GraphInitialization>(Parameters::getInt(parameters, Parameters::kOptimizerInit()));
  o.robust = Parameters::getBool(parameters, Parameters::kOptimizerRobust());
  o.robustLoss =
      static_cast<RobustLoss>(Parameters::getInt(parameters, Parameters::kOptimizerRobustLoss()));
  o.robustWidth = Parameters::getDouble(parameters, Parameters::kOptimizerRobustWidth());
  o.priorsIgnored = Parameters::getBool(parameters, Parameters::kOptimizerPriorsIgnored());
  o.landmarksIgnored = Parameters::getBool(parameters, Parameters::kOptimizerLandmarksIgnored());
  o.varianceIgnored = Parameters::getBool(parameters, Parameters::kOptimizerVarianceIgnored());
  o.gravitySigma = Parameters::getDouble(parameters, Parameters::kOptimizerGravitySigma());
  o.force3DoF = Parameters::getBool(parameters, Parameters::kRegForce3DoF());
  return o;
}

bool OptimizerOptions::IsValid(std::string* why) const {
  std::ostringstream reason;
  if (iterations < 1) {
    reason << "Optimizer/Iterations must be at least 1 (got " << iterations << ")";
  } else if (!(epsilon >= 0.0) || !std::isfinite(epsilon)) {
    reason << "Optimizer/Epsilon must be a finite number >= 0 (got " << epsilon << ")";
  } else if (initialization != GraphInitialization::kInputPoses &&
             initialization != GraphInitialization::kSpanningTree &&
             initialization != GraphInitialization::kChordal) {
    reason << "Optimizer/Init must be 0 (input poses), 1 (spanning tree) or 2 (chordal) (got "
           << static_cast<int>(initialization) << ")";
  } else if (robustLoss != RobustLoss::kCauchy && robustLoss != RobustLoss::kHuber) {
    reason << "Optimizer/RobustLoss must be 0 (Cauchy) or 1 (Huber) (got "
           << static_cast<int>(robustLoss) << ")";
  } else if (!(robustWidth > 0.0) || !std::isfinite(robustWidth)) {
    reason << "Optimizer/RobustWidth must be a finite number > 0 (got " << robustWidth << ")";
  } else if (!(gravitySigma >= 0.0) || !std::isfinite(gravitySigma)) {
    reason << "Optimizer/GravitySigma must be a finite number >= 0 (got " << gravitySigma << ")";
  } else if (numThreads < 1) {
    reason << "the optimiser needs at least 1 thread (got " << numThreads << ")";
  } else if (!(gradientTolerance >= 0.0) || !(parameterTolerance >= 0.0)) {
    reason << "the gradient and parameter tolerances must be >= 0";
  }
  const std::string text = reason.str();
  if (why) *why = text;
  return text.empty();
}

}  // namespace rtabmap
