// rtabmap-export: maps for navigation from a database: the 2D occupancy grid (PGM + map_server
// YAML + PNG preview), the OctoMap (.bt / .ot), the point cloud (.ply / .pcd), the poses (TUM).
#include <filesystem>
#include <iostream>
#include <memory>

#include "common/CommandLine.h"
#include "common/Json.h"
#include "common/ProgressBar.h"
#include "export/Export.h"
#include "rtabmap_core/db/Database.h"

namespace {

std::string extension(const std::string& path) {
  return std::filesystem::path(path).extension().string();
}

}  // namespace

int main(int argc, char** argv) {
  using namespace rtabmap;
  return tools::runTool("rtabmap-export", [&] {
    tools::CommandLine cli(
        "rtabmap-export",
        "Writes the maps of an rtabmap_ros database: the global 2D occupancy grid as map_server "
        "reads it, the OctoMap, the assembled point cloud and the node poses. The poses are the "
        "graph optimised with every link of the database (each connected map on its own, its "
        "oldest node fixed), as the SLAM node has them when it opens the database. Maps are "
        "assembled from the local grid stored with each node; nodes stored without one get it computed from "
        "their laser scan or depth image with the Grid/* parameters (the database's, overridden "
        "by --Grid/... arguments).");
    cli.addPositional("database", "The database (.db), opened read-only.");
    cli.addOption("grid", "OUT.pgm",
                  "2D occupancy grid: OUT.pgm, OUT.yaml (map_server: image, resolution, origin, "
                  "negate, occupied_thresh, free_thresh) and OUT.png (preview).");
    cli.addOption("octomap", "OUT.bt|OUT.ot", "OctoMap: .bt (occupancy) or .ot (with colours).");
    cli.addOption("cloud", "OUT.ply|OUT.pcd", "Assembled point cloud (obstacles and ground, voxel filtered).");
    cli.addOption("poses", "OUT.tum", "Optimised node poses, one line per node: stamp x y z qx qy qz qw.");
    cli.addFlag("regenerate", "Compute every local grid again from the sensor data, even when one is stored.");
    cli.addOption("png-scale", "N", "Enlarge the PNG preview N times.", "1");
    cli.addNote("Example: rtabmap-export --grid map.pgm --octomap map.bt --cloud map.ply ~/.ros/rtabmap.db");
    cli.addNote("map_server: rosrun map_server map_server map.yaml");
    if (auto exitCode = cli.parse(argc, argv)) return *exitCode;

    tools::exporter::Request req;
    req.database = cli.positional("database");
    if (cli.has("grid")) req.gridPath = cli.option("grid");
    if (cli.has("octomap")) req.octomapPath = cli.option("octomap");
    if (cli.has("cloud")) req.cloudPath = cli.option("cloud");
    if (cli.has("poses")) req.posesPath = cli.option("poses");
    if (req.gridPath.empty() && req.octomapPath.empty() && req.cloudPath.empty() && req.posesPath.empty()) {
      throw tools::UsageError("nothing to export: give at least one of --grid, --octomap, --cloud, --poses");
    }
    if (!req.gridPath.empty() && extension(req.gridPath) != ".pgm") {
      throw tools::UsageError("--grid must end with .pgm (got '" + req.gridPath + "')");
    }
    const std::string octoExt = extension(req.octomapPath);
    if (!req.octomapPath.empty() && octoExt != ".bt" && octoExt != ".ot") {
      throw tools::UsageError("--octomap must end with .bt or .ot (got '" + req.octomapPath + "')");
    }
    const std::string cloudExt = extension(req.cloudPath);
    if (!req.cloudPath.empty() && cloudExt != ".ply" && cloudExt != ".pcd") {
      throw tools::UsageError("--cloud must end with .ply or .pcd (got '" + req.cloudPath + "')");
    }
    req.regenerate = cli.flag("regenerate");
    req.pngScale = cli.optionInt("png-scale");
    if (req.pngScale < 1) throw tools::UsageError("--png-scale must be at least 1");
    req.parameters = cli.parameters();
    req.cellSizeGiven = cli.parameters().count(Parameters::kGridCellSize()) > 0;

    std::unique_ptr<tools::ProgressBar> bar;
    const tools::exporter::Report report = tools::exporter::run(req, [&](size_t done, size_t total) {
      if (!bar) bar = std::make_unique<tools::ProgressBar>("assembling nodes", total, cli);
      bar->update(done);
    });
    if (bar) bar->finish();
    if (!cli.json()) {
      for (const std::string& w : report.warnings) std::cerr << "rtabmap-export: warning: " << w << "\n";
      std::cout << tools::exporter::describe(report);
    } else {
      tools::printJsonLine(report.json);
    }
    return tools::kExitSuccess;
  });
}
