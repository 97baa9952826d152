// rtabmap-info: what a long-term-memory database holds (sessions, nodes, links per type,
// words, size), read-only.
#include <iostream>
#include <optional>

#include "common/CommandLine.h"
#include "common/Json.h"
#include "info/Report.h"
#include "rtabmap_core/db/Database.h"

int main(int argc, char** argv) {
  return rtabmap::tools::runTool("rtabmap-info", [&] {
    rtabmap::tools::CommandLine cli(
        "rtabmap-info",
        "Prints what an rtabmap_ros database holds: schema version, sessions and their map ids, "
        "nodes, links per type, visual words and size on disk. The database is opened read-only.");
    cli.addPositional("database", "Path of the database (.db).");
    cli.addFlag("params-db", "Also print the parameters stored with the last session.");
    cli.addFlag("check", "Also check the database: cross-table consistency and SQLite's quick_check (reads the whole file).");
    cli.addNote("Example: rtabmap-info --json ~/.ros/rtabmap.db | tail -n 1");
    if (auto exitCode = cli.parse(argc, argv)) return *exitCode;

    rtabmap::db::Database::Options options;
    options.readOnly = true;
    rtabmap::db::Database db(cli.positional("database"), options);
    const rtabmap::db::DatabaseSummary summary = db.summary();
    std::optional<rtabmap::db::ConsistencyReport> consistency;
    if (cli.flag("check")) consistency = db.checkConsistency(true);
    std::optional<std::string> parameters;
    if (cli.flag("params-db")) parameters = db.lastSessionParameters();

    if (cli.json()) {
      rtabmap::tools::printJsonLine(rtabmap::tools::info::toJson(summary, consistency, parameters));
    } else {
      rtabmap::tools::info::printText(std::cout, summary, consistency, parameters);
    }
    return (consistency && !consistency->ok()) ? rtabmap::tools::kExitFailure : rtabmap::tools::kExitSuccess;
  });
}
