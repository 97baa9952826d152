#pragma once
// Map files: the 2D grid as map_server reads it (PGM + YAML), a PNG preview, and point clouds
// as PLY and PCD (written here: both formats are short documented headers followed by binary
// little-endian records; readers of what we write come along for round trips).
//
// map_server conventions (negate 0): a pixel p of the PGM has occupancy (255 - p) / 255; it is
// occupied above occupied_thresh, free below free_thresh, unknown between. We write occupied 0,
// free 254, unknown 205 with thresholds 0.65 / 0.196, so every cell reads back to its value.
// The image's first row is the map's top (highest y); origin is the map's lower-left corner.
#include <string>

#include "rtabmap_core/maps/Cloud.h"
#include "rtabmap_core/maps/GridMap.h"

namespace rtabmap {

// Image of a grid as map_server expects it (CV_8UC1, top row = highest y).
cv::Mat gridToPgmImage(const GridMap& map);
// Writes <pgmPath> and the YAML at yamlPath (its `image:` is the PGM's file name, relative).
// Throws FormatError if the map is empty or a file cannot be written.
void writeMapServer(const GridMap& map, const std::string& pgmPath, const std::string& yamlPath);
// Reads a map_server YAML and its image (PGM or PNG, relative to the YAML's folder), with
// map_server's trinary interpretation (negate, thresholds honoured). Throws FormatError naming
// the file on anything malformed.
GridMap readMapServer(const std::string& yamlPath);
// A PNG preview: free white, occupied black, unknown grey, top row = highest y; `scale` > 1
// enlarges it (nearest neighbour). Throws FormatError on an empty map or a write failure.
void writeGridPng(const GridMap& map, const std::string& pngPath, int scale = 1);

// Point clouds (binary little endian; colour written when the cloud has it). Throw FormatError
// on an empty cloud or a write failure.
void writePly(const Cloud& cloud, const std::string& path);
void writePcd(const Cloud& cloud, const std::string& path);
// Readers of binary little-endian files with float x y z and optional colour (PLY: uchar
// red green blue; PCD: packed rgb float). Throw FormatError otherwise.
Cloud readPly(const std::string& path);
Cloud readPcd(const std::string& path);

}  // namespace rtabmap
