#pragma once
// Options of the SLAM pipeline (Rtabmap::process), read once from the parameters: the RGBD/,
// Rtabmap/ and Mem/ keys the pipeline itself reads. The parts it delegates (memory and loop
// closure, registration, optimiser, grids) read their own groups.
#include <string>

#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {

struct RtabmapOptions {
  // Rate and map update
  float detectionRate = 1.0f;     // Rtabmap/DetectionRate (Hz, 0 = every input)
  bool createIntermediateNodes = false;    // Rtabmap/CreateIntermediateNodes
  bool intermediateNodeDataKept = false;   // Mem/IntermediateNodeDataKept
  bool metric = true;             // RGBD/Enabled
  bool incremental = true;        // Mem/IncrementalMemory (false = localization)
  float linearUpdate = 0.1f;      // RGBD/LinearUpdate (m)
  float angularUpdate = 0.1f;     // RGBD/AngularUpdate (rad)
  float newMapOdomChangeDistance = 0.0f;  // RGBD/NewMapOdomChangeDistance (m)
  bool createOccupancyGrid = false;       // RGBD/CreateOccupancyGrid
  bool useOdomFeatures = true;            // Mem/UseOdomFeatures
  bool covOffDiagIgnored = true;          // Mem/CovOffDiagIgnored
  bool imageKept = false;                 // Mem/ImageKept
  bool binDataKept = true;                // Mem/BinDataKept
  std::string imageFormat = ".jpg";       // Mem/ImageCompressionFormat
  int imagePreDecimation = 1;             // Mem/ImagePreDecimation
  int imagePostDecimation = 1;            // Mem/ImagePostDecimation
  bool saveDepth16 = false;               // Mem/SaveDepth16Format
  bool compressionParallelized = true;    // Mem/CompressionParallelized
  bool imagesAlreadyRectified = true;     // Rtabmap/ImagesAlreadyRectified
  bool computeRmse = true;                // Rtabmap/ComputeRMSE
  bool loopClosureReextractFeatures = false;  // RGBD/LoopClosureReextractFeatures
  bool localBundleOnLoopClosure = false;      // RGBD/LocalBundleOnLoopClosure
  bool publishStats = true;               // Rtabmap/PublishStats
  bool publishPdf = true;                 // Rtabmap/PublishPdf
  bool publishLikelihood = true;          // Rtabmap/PublishLikelihood
  bool saveWmState = false;               // Rtabmap/SaveWMState
  bool generateIds = true;                // Mem/GenerateIds
  bool mapLabelsAdded = true;             // Mem/MapLabelsAdded
  bool startNewMapOnLoopClosure = false;  // Rtabmap/StartNewMapOnLoopClosure
  bool startNewMapOnGoodSignature = false;  // Rtabmap/StartNewMapOnGoodSignature
  bool initWMWithAllNodes = false;        // Mem/InitWMWithAllNodes
  // Links
  int regStrategy = 0;                    // Reg/Strategy: 0 visual, 1 ICP, 2 visual then ICP
  bool force3DoF = false;                 // Reg/Force3DoF
  bool loopClosureIdentityGuess = false;  // RGBD/LoopClosureIdentityGuess
  bool neighborLinkRefining = false;      // RGBD/NeighborLinkRefining
  float neighborLinkRefiningPrior = 0.0f; // RGBD/NeighborLinkRefiningPrior (fraction of the step)
  bool loopCovLimited = false;            // RGBD/LoopCovLimited
  // Proximity detection by space (SPLAM paper, 3.3.3)
  bool proximityBySpace = true;           // RGBD/ProximityBySpace
  bool proximityByTime = false;           // RGBD/ProximityByTime
  float localRadius = 10.0f;              // RGBD/LocalRadius (m)
  int proximityMaxGraphDepth = 50;        // RGBD/ProximityMaxGraphDepth (0 = no limit)
  int proximityMaxPaths = 3;              // RGBD/ProximityMaxPaths (0 = no limit)
  float proximityPathFilteringRadius = 1.0f;  // RGBD/ProximityPathFilteringRadius (m)
  int proximityPathMaxNeighbors = 0;      // RGBD/ProximityPathMaxNeighbors
  bool proximityPathRawPosesUsed = true;  // RGBD/ProximityPathRawPosesUsed
  float proximityAngle = 45.0f;           // RGBD/ProximityAngle (deg)
  bool proximityOdomGuess = false;        // RGBD/ProximityOdomGuess
  double proximityMergedScanCovFactor = 100.0;  // RGBD/ProximityMergedScanCovFactor
  bool scanMatchingIdsSavedInLinks = true;       // RGBD/ScanMatchingIdsSavedInLinks
  float proximityCorrelativeWindow = 0.0f;      // RGBD/ProximityCorrelativeWindow (m, 0 = off)
  float proximityCorrelativeAngle = 20.0f;      // RGBD/ProximityCorrelativeAngle (deg)
  float proximityCorrelativeMinScore = 0.6f;    // RGBD/ProximityCorrelativeMinScore
  float proximityCorrelativeResolution = 0.1f;  // RGBD/ProximityCorrelativeResolution (m)
  float proximityCorrelativeMaxPeakRatio = 0.9f;  // RGBD/ProximityCorrelativeMaxPeakRatio (1 = off)
  float proximityCorrelativeSigmas = 3.0f;      // RGBD/ProximityCorrelativeSigmas (0 = whole window)
  bool proximityGlobalScanMap = false;          // RGBD/ProximityGlobalScanMap (localization mode)
  float proximityGlobalScanMapMinRatio = 0.7f;  // RGBD/ProximityGlobalScanMapMinRatio
  // Graph
  float optimizeMaxError = 3.0f;          // RGBD/OptimizeMaxError (standard deviations, 0 = off)
  bool optimizeFromGraphEnd = false;      // RGBD/OptimizeFromGraphEnd
  float maxLoopClosureDistance = 0.0f;    // RGBD/MaxLoopClosureDistance (m, 0 = off)
  // Memory management around the robot
  int maxLocalRetrieved = 2;              // RGBD/MaxLocalRetrieved
  float localImmunizationRatio = 0.25f;   // RGBD/LocalImmunizationRatio
  // Map updates skipped while the robot moves faster (odometry between consecutive frames)
  float linearSpeedUpdate = 0.0f;         // RGBD/LinearSpeedUpdate (m/s, 0 = no limit)
  float angularSpeedUpdate = 0.0f;        // RGBD/AngularSpeedUpdate (rad/s, 0 = no limit)
  // Localization
  bool startAtOrigin = false;             // RGBD/StartAtOrigin
  int maxOdomCacheSize = 10;              // RGBD/MaxOdomCacheSize
  // Path planning
  bool goalsSavedInUserData = false;      // RGBD/GoalsSavedInUserData

  // Throws ParameterError on an undeclared key or an invalid value (naming the key).
  static RtabmapOptions fromParameters(const ParametersMap& parameters);
  bool IsValid(std::string* why = nullptr) const;
};

}  // namespace rtabmap
