#include "export/Export.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <memory>
#include <optional>
#include <sstream>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/maps/CloudMap.h"
#include "rtabmap_core/maps/LocalGridMaker.h"
#include "rtabmap_core/maps/MapIO.h"
#include "rtabmap_core/maps/OccupancyGrid.h"
#include "rtabmap_core/maps/OctoMap.h"
#include "rtabmap_core/optimizer/Optimizer.h"

namespace rtabmap::tools::exporter {

namespace fs = std::filesystem;

namespace {

constexpr size_t kBatch = 100;  // nodes loaded at once: bounded memory on big databases

std::string withExtension(const std::string& path, const char* ext) {
  return fs::path(path).replace_extension(ext).string();
}

// The maps asked for, made once the cell size is known (from the first local grid).
struct Maps {
  std::unique_ptr<OccupancyGrid> grid;
  std::unique_ptr<OctoMap> octomap;
  std::unique_ptr<CloudMap> cloud;
  float cellSize = 0.0f;
};

void createMaps(const Request& req, ParametersMap params, float cellSize, Maps& maps) {
  params[Parameters::kGridCellSize()] = std::to_string(cellSize);
  maps.cellSize = cellSize;
  if (!req.gridPath.empty()) maps.grid = std::make_unique<OccupancyGrid>(GlobalGridOptions::fromParameters(params));
  if (!req.octomapPath.empty()) maps.octomap = std::make_unique<OctoMap>(OctoMapOptions::fromParameters(params));
  if (!req.cloudPath.empty()) maps.cloud = std::make_unique<CloudMap>(CloudMapOptions::fromParameters(params));
}

std::map<int, Transform> storedPoses(const std::map<int, Signature>& headers, int* nullPoses) {
  std::map<int, Transform> poses;
  for (const auto& [id, s] : headers) {
    if (s.getPose().isNull() || s.getPose().isInvalid()) ++*nullPoses;
    else poses[id] = s.getPose();
  }
  return poses;
}

void writePoses(const std::string& path, const std::map<int, Transform>& poses,
                const std::map<int, Signature>& headers) {
  std::ofstream f(path);
  if (!f) throw FormatError("cannot write " + path);
  f << std::setprecision(9);
  for (const auto& [id, p] : poses) {
    const Eigen::Quaterniond q = p.quaternion();
    f << std::fixed << std::setprecision(6) << headers.at(id).stamp() << std::defaultfloat
      << std::setprecision(9) << " " << p.x() << " " << p.y() << " " << p.z() << " " << q.x() << " "
      << q.y() << " " << q.z() << " " << q.w() << "\n";
  }
  if (!f) throw FormatError("cannot write " + path);
}

}  // namespace

Report run(const Request& req, const std::function<void(size_t, size_t)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  Report report;
  nlohmann::json& j = report.json;
  db::Database::Options dbOptions;
  dbOptions.readOnly = true;
  db::Database database(req.database, dbOptions);

  // Parameters: the session's (what made the stored grids), then the command line's.
  ParametersMap params = Parameters::deserializeLenient(database.lastSessionParameters()).known;
  for (const auto& [k, v] : req.parameters) params[k] = v;
  LocalGridOptions local = LocalGridOptions::fromParameters(params);

  const std::map<int, Signature> headers = database.loadAllNodeHeaders();
  if (headers.empty()) throw FormatError("database " + req.database + " holds no node");
  int nullPoses = 0;
  std::map<int, Transform> poses = storedPoses(headers, &nullPoses);
  if (nullPoses) report.warnings.push_back(std::to_string(nullPoses) + " node(s) have no pose and are left out");
  if (poses.empty()) throw FormatError("database " + req.database + ": no node has a pose");
  // The stored poses are odometry; the map is the graph optimised with every link, as the
  // SLAM node does when it opens the database.
  std::vector<std::string> notOptimised;
  poses = optimizeEachComponent(OptimizerOptions::fromParameters(params), poses, database.loadAllLinks(false),
                                &notOptimised);
  for (const std::string& why : notOptimised) report.warnings.push_back(why);

  Maps maps;
  const bool needGrids = !req.gridPath.empty() || !req.octomapPath.empty() || !req.cloudPath.empty();
  int stored = 0, regenerated = 0, failed = 0, rejected = 0;
  std::map<std::string, int> failures;  // reason -> count (reported once each)
  if (needGrids) {
    std::vector<int> ids;
    for (const auto& [id, p] : poses) ids.push_back(id);
    db::LoadOptions gridOnly = db::LoadOptions::nodeOnly();
    gridOnly.grid = true;
    db::LoadOptions sensors = db::LoadOptions::nodeOnly();
    sensors.image = sensors.depthOrRight = sensors.scan = true;
    for (size_t b = 0; b < ids.size(); b += kBatch) {
      const std::vector<int> batch(ids.begin() + b, ids.begin() + std::min(ids.size(), b + kBatch));
      std::vector<Signature> nodes = database.loadNodes(batch, req.regenerate ? db::LoadOptions::nodeOnly() : gridOnly);
      for (Signature& node : nodes) {
        LocalGrid grid = node.sensorData().localGrid();
        if (!grid.isEmpty() && !req.regenerate && (!req.cellSizeGiven || std::abs(grid.cellSize - local.cellSize) < 1e-6f)) {
          ++stored;
        } else {
          std::optional<Signature> full = database.loadNode(node.id(), sensors);
          LocalGridResult r;
          if (full) {
            SensorData data = full->sensorData();
            data.uncompress();
            r = createLocalGrid(data, local);
          } else {
            r.why = "node vanished from the database";
          }
          if (!r.success) {
            ++failed;
            ++failures[r.why];
            continue;
          }
          ++regenerated;
          grid = r.grid;
        }
        if (!maps.cellSize) createMaps(req, params, grid.cellSize, maps);
        std::string why;
        bool ok = true;
        if (maps.grid) ok = maps.grid->addLocalGrid(node.id(), grid, &why) && ok;
        if (maps.octomap) ok = maps.octomap->addLocalGrid(node.id(), grid, &why) && ok;
        if (maps.cloud) ok = maps.cloud->addLocalGrid(node.id(), grid, &why) && ok;
        if (!ok) {
          ++rejected;
          ++failures[why.substr(why.find(':') + 2)];
        }
      }
      if (progress) progress(std::min(ids.size(), b + kBatch), ids.size());
    }
    for (const auto& [why, count] : failures) {
      report.warnings.push_back(std::to_string(count) + " node(s) without a usable local grid: " + why);
    }
    if (!maps.cellSize) {
      throw FormatError("no node of " + req.database + " has a usable local grid" +
                        (failures.empty() ? std::string() : " (" + failures.begin()->first + ")"));
    }
  }
  j["database"] = req.database;
  j["nodes"] = headers.size();
  j["nodes_with_pose"] = poses.size();
  j["grids_stored"] = stored;
  j["grids_regenerated"] = regenerated;
  j["grids_failed"] = failed + rejected;
  j["cell_size"] = maps.cellSize;
  nlohmann::json outputs = nlohmann::json::object();

  if (maps.grid) {
    const GridUpdateSummary s = maps.grid->update(poses);
    const GridMap m = maps.grid->map();
    if (m.empty()) throw FormatError("the 2D grid is empty: no node's local grid could be placed");
    const std::string yaml = withExtension(req.gridPath, ".yaml"), png = withExtension(req.gridPath, ".png");
    writeMapServer(m, req.gridPath, yaml);
    writeGridPng(m, png, req.pngScale);
    outputs["grid"] = {{"pgm", req.gridPath}, {"yaml", yaml}, {"png", png}, {"width", m.width()},
                       {"height", m.height()}, {"resolution", m.resolution},
                       {"origin", {m.originX, m.originY}}, {"occupied", m.countOccupied()},
                       {"free", m.countFree()}, {"unknown", m.countUnknown()},
                       {"nodes", s.nodesAssembled}, {"time_ms", s.timeMs}};
  }
  if (maps.octomap) {
    const OctoMapUpdateSummary s = maps.octomap->update(poses);
    const bool ok = fs::path(req.octomapPath).extension() == ".bt" ? maps.octomap->writeBinary(req.octomapPath)
                                                                   : maps.octomap->write(req.octomapPath);
    if (!ok) throw FormatError("cannot write the OctoMap to " + req.octomapPath + (maps.octomap->empty() ? " (it is empty)" : ""));
    outputs["octomap"] = {{"path", req.octomapPath}, {"leaves", maps.octomap->leafCount()},
                          {"nodes", s.nodesInserted}, {"time_ms", s.timeMs}};
  }
  if (maps.cloud) {
    maps.cloud->update(poses);
    const Cloud& c = maps.cloud->cloud();
    if (fs::path(req.cloudPath).extension() == ".ply") writePly(c, req.cloudPath);
    else writePcd(c, req.cloudPath);
    outputs["cloud"] = {{"path", req.cloudPath}, {"points", c.size()}, {"colored", c.hasColors()}};
  }
  if (!req.posesPath.empty()) {
    writePoses(req.posesPath, poses, headers);
    outputs["poses"] = {{"path", req.posesPath}, {"count", poses.size()}};
  }
  j["outputs"] = outputs;
  j["warnings"] = report.warnings;
  j["time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

std::string describe(const Report& report) {
  const nlohmann::json& j = report.json;
  std::ostringstream s;
  s << "database: " << j["database"].get<std::string>() << "\n"
    << "nodes: " << j["nodes"] << " (" << j["nodes_with_pose"] << " with a pose)\n"
    << "local grids: " << j["grids_stored"] << " stored, " << j["grids_regenerated"] << " computed, "
    << j["grids_failed"] << " unusable; cell size " << j["cell_size"] << " m\n";
  const nlohmann::json& o = j["outputs"];
  if (o.contains("grid")) {
    const auto& g = o["grid"];
    s << "grid: " << g["pgm"].get<std::string>() << " + " << g["yaml"].get<std::string>() << " + "
      << g["png"].get<std::string>() << ": " << g["width"] << " x " << g["height"] << " cells, "
      << g["occupied"] << " occupied, " << g["free"] << " free\n";
  }
  if (o.contains("octomap")) {
    s << "octomap: " << o["octomap"]["path"].get<std::string>() << ": " << o["octomap"]["leaves"] << " leaves\n";
  }
  if (o.contains("cloud")) {
    s << "cloud: " << o["cloud"]["path"].get<std::string>() << ": " << o["cloud"]["points"] << " points\n";
  }
  if (o.contains("poses")) {
    s << "poses: " << o["poses"]["path"].get<std::string>() << ": " << o["poses"]["count"] << " nodes\n";
  }
  return s.str();
}

}  // namespace rtabmap::tools::exporter
