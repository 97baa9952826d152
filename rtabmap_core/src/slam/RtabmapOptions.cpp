#include "rtabmap_core/slam/RtabmapOptions.h"

#include <cmath>

#include "rtabmap_core/common/Error.h"

namespace rtabmap {

RtabmapOptions RtabmapOptions::fromParameters(const ParametersMap& p) {
  using P = Parameters;
  RtabmapOptions o;
  o.detectionRate = P::getFloat(p, P::kRtabmapDetectionRate());
  o.createIntermediateNodes = P::getBool(p, P::kRtabmapCreateIntermediateNodes());
  o.intermediateNodeDataKept = P::getBool(p, P::kMemIntermediateNodeDataKept());
  o.metric = P::getBool(p, P::kRGBDEnabled());
  o.incremental = P::getBool(p, P::kMemIncrementalMemory());
  o.linearUpdate = P::getFloat(p, P::kRGBDLinearUpdate());
  o.angularUpdate = P::getFloat(p, P::kRGBDAngularUpdate());
  o.newMapOdomChangeDistance = P::getFloat(p, P::kRGBDNewMapOdomChangeDistance());
  o.createOccupancyGrid = P::getBool(p, P::kRGBDCreateOccupancyGrid());
  o.useOdomFeatures = P::getBool(p, P::kMemUseOdomFeatures());
  o.covOffDiagIgnored = P::getBool(p, P::kMemCovOffDiagIgnored());
  o.imageKept = P::getBool(p, P::kMemImageKept());
  o.binDataKept = P::getBool(p, P::kMemBinDataKept());
  o.imageFormat = P::getString(p, P::kMemImageCompressionFormat());
  o.imagePreDecimation = P::getInt(p, P::kMemImagePreDecimation());
  o.imagePostDecimation = P::getInt(p, P::kMemImagePostDecimation());
  o.saveDepth16 = P::getBool(p, P::kMemSaveDepth16Format());
  o.compressionParallelized = P::getBool(p, P::kMemCompressionParallelized());
  o.imagesAlreadyRectified = P::getBool(p, P::kRtabmapImagesAlreadyRectified());
  o.computeRmse = P::getBool(p, P::kRtabmapComputeRMSE());
  o.loopClosureReextractFeatures = P::getBool(p, P::kRGBDLoopClosureReextractFeatures());
  o.localBundleOnLoopClosure = P::getBool(p, P::kRGBDLocalBundleOnLoopClosure());
  o.publishStats = P::getBool(p, P::kRtabmapPublishStats());
  o.publishPdf = P::getBool(p, P::kRtabmapPublishPdf());
  o.publishLikelihood = P::getBool(p, P::kRtabmapPublishLikelihood());
  o.saveWmState = P::getBool(p, P::kRtabmapSaveWMState());
  o.generateIds = P::getBool(p, P::kMemGenerateIds());
  o.mapLabelsAdded = P::getBool(p, P::kMemMapLabelsAdded());
  o.startNewMapOnLoopClosure = P::getBool(p, P::kRtabmapStartNewMapOnLoopClosure());
  o.startNewMapOnGoodSignature = P::getBool(p, P::kRtabmapStartNewMapOnGoodSignature());
  o.initWMWithAllNodes = P::getBool(p, P::kMemInitWMWithAllNodes());
  o.regStrategy = P::getInt(p, P::kRegStrategy());
  o.force3DoF = P::getBool(p, P::kRegForce3DoF());
  o.loopClosureIdentityGuess = P::getBool(p, P::kRGBDLoopClosureIdentityGuess());
  o.neighborLinkRefining = P::getBool(p, P::kRGBDNeighborLinkRefining());
  o.neighborLinkRefiningPrior = P::getFloat(p, P::kRGBDNeighborLinkRefiningPrior());
  o.loopCovLimited = P::getBool(p, P::kRGBDLoopCovLimited());
  o.proximityBySpace = P::getBool(p, P::kRGBDProximityBySpace());
  o.proximityByTime = P::getBool(p, P::kRGBDProximityByTime());
  o.localRadius = P::getFloat(p, P::kRGBDLocalRadius());
  o.proximityMaxGraphDepth = P::getInt(p, P::kRGBDProximityMaxGraphDepth());
  o.proximityMaxPaths = P::getInt(p, P::kRGBDProximityMaxPaths());
  o.proximityPathFilteringRadius = P::getFloat(p, P::kRGBDProximityPathFilteringRadius());
  o.proximityPathMaxNeighbors = P::getInt(p, P::kRGBDProximityPathMaxNeighbors());
  o.proximityPathRawPosesUsed = P::getBool(p, P::kRGBDProximityPathRawPosesUsed());
  o.proximityAngle = P::getFloat(p, P::kRGBDProximityAngle());
  o.proximityOdomGuess = P::getBool(p, P::kRGBDProximityOdomGuess());
  o.proximityMergedScanCovFactor = P::getDouble(p, P::kRGBDProximityMergedScanCovFactor());
  o.scanMatchingIdsSavedInLinks = P::getBool(p, P::kRGBDScanMatchingIdsSavedInLinks());
  o.proximityCorrelativeWindow = P::getFloat(p, P::kRGBDProximityCorrelativeWindow());
  o.proximityCorrelativeAngle = P::getFloat(p, P::kRGBDProximityCorrelativeAngle());
  o.proximityCorrelativeMinScore = P::getFloat(p, P::kRGBDProximityCorrelativeMinScore());
  o.proximityCorrelativeResolution = P::getFloat(p, P::kRGBDProximityCorrelativeResolution());
  o.proximityCorrelativeMaxPeakRatio = P::getFloat(p, P::kRGBDProximityCorrelativeMaxPeakRatio());
  o.proximityCorrelativeSigmas = P::getFloat(p, P::kRGBDProximityCorrelativeSigmas());
  o.proximityGlobalScanMap = P::getBool(p, P::kRGBDProximityGlobalScanMap());
  o.proximityGlobalScanMapMinRatio = P::getFloat(p, P::kRGBDProximityGlobalScanMapMinRatio());
  o.optimizeMaxError = P::getFloat(p, P::kRGBDOptimizeMaxError());
  o.optimizeFromGraphEnd = P::getBool(p, P::kRGBDOptimizeFromGraphEnd());
  o.maxLoopClosureDistance = P::getFloat(p, P::kRGBDMaxLoopClosureDistance());
  o.maxLocalRetrieved = P::getInt(p, P::kRGBDMaxLocalRetrieved());
  o.localImmunizationRatio = P::getFloat(p, P::kRGBDLocalImmunizationRatio());
  o.linearSpeedUpdate = P::getFloat(p, P::kRGBDLinearSpeedUpdate());
  o.angularSpeedUpdate = P::getFloat(p, P::kRGBDAngularSpeedUpdate());
  o.startAtOrigin = P::getBool(p, P::kRGBDStartAtOrigin());
  o.maxOdomCacheSize = P::getInt(p, P::kRGBDMaxOdomCacheSize());
  o.goalsSavedInUserData = P::getBool(p, P::kRGBDGoalsSavedInUserData());
  std::string why;
  if (!o.IsValid(&why)) throw ParameterError(why);
  return o;
}

bool RtabmapOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (!(detectionRate >= 0.0f) || !std::isfinite(detectionRate)) return fail(Parameters::kRtabmapDetectionRate() + " must be >= 0");
  if (regStrategy < 0 || regStrategy > 2) return fail(Parameters::kRegStrategy() + " must be 0, 1 or 2");
  if (!(localRadius > 0.0f)) return fail(Parameters::kRGBDLocalRadius() + " must be > 0");
  if (proximityPathMaxNeighbors < 0 || proximityMaxPaths < 0 || proximityMaxGraphDepth < 0) {
    return fail("RGBD/ProximityPathMaxNeighbors, RGBD/ProximityMaxPaths and RGBD/ProximityMaxGraphDepth must be >= 0");
  }
  if (!(proximityMergedScanCovFactor > 0.0)) return fail(Parameters::kRGBDProximityMergedScanCovFactor() + " must be > 0");
  if (!(proximityGlobalScanMapMinRatio >= 0.0f && proximityGlobalScanMapMinRatio <= 1.0f)) {
    return fail(Parameters::kRGBDProximityGlobalScanMapMinRatio() + " must be in [0, 1]");
  }
  if (!(proximityCorrelativeWindow >= 0.0f) || !(proximityCorrelativeSigmas >= 0.0f) ||
      !(proximityCorrelativeResolution > 0.0f) || !(proximityCorrelativeAngle >= 0.0f)) {
    return fail("RGBD/ProximityCorrelativeWindow, RGBD/ProximityCorrelativeSigmas and RGBD/ProximityCorrelativeAngle "
                "must be >= 0, RGBD/ProximityCorrelativeResolution > 0");
  }
  if (!(proximityCorrelativeMinScore > 0.0f && proximityCorrelativeMinScore <= 1.0f) ||
      !(proximityCorrelativeMaxPeakRatio > 0.0f && proximityCorrelativeMaxPeakRatio <= 1.0f)) {
    return fail("RGBD/ProximityCorrelativeMinScore and RGBD/ProximityCorrelativeMaxPeakRatio must be in (0, 1]");
  }
  if (!(neighborLinkRefiningPrior >= 0.0f) || !std::isfinite(neighborLinkRefiningPrior)) {
    return fail(Parameters::kRGBDNeighborLinkRefiningPrior() + " must be >= 0");
  }
  if (!(optimizeMaxError >= 0.0f)) return fail(Parameters::kRGBDOptimizeMaxError() + " must be >= 0");
  if (imagePreDecimation < 1 || imagePostDecimation < 1) {
    return fail("Mem/ImagePreDecimation and Mem/ImagePostDecimation must be >= 1");
  }
  if (!incremental && !metric) {
    return fail(Parameters::kMemIncrementalMemory() + " false (localization) needs " + Parameters::kRGBDEnabled() + " true");
  }
  return true;
}

}  // namespace rtabmap
