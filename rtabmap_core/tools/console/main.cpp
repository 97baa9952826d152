// rtabmap-console: appearance-only loop-closure detection over a folder of images, one location
// per image as in the T-RO 2013 experiments. Writes the database (the long-term memory), a
// per-image log and the detections file that `rtabmap-eval pr` scores.
#include <iostream>

#include "common/CommandLine.h"
#include "common/Json.h"
#include "console/ConsoleRun.h"

int main(int argc, char** argv) {
  return rtabmap::tools::runTool("rtabmap-console", [&] {
    rtabmap::tools::CommandLine cli(
        "rtabmap-console",
        "Appearance-based loop-closure detection (RTAB-Map, T-RO 2013) over the images of a folder, "
        "in the natural order of their names, one location per image.");
    cli.addPositionalList("inputs",
                          "Folder of images (jpg, png, bmp, pgm, ...), or datasets of --format. Several: processed "
                          "one after the other by the same memory, as sessions of one map.",
                          1);
    cli.addOption("output", "DIR", "Where to write rtabmap.db (overwritten), log.txt and detections.txt.", ".");
    cli.addOption("gt", "FILE",
                  "Ground-truth loop matrix (N x N image, e.g. GT.png / GT.bmp, or text): prints precision, "
                  "recall and the recall at 100% precision.");
    cli.addOption("max-images", "N", "Stop after N images (0 = all).", "0");
    cli.addOption("format", "NAME",
                  "Dataset layout of the input (images, 7scenes, tum, euroc, kitti, sim): its camera images "
                  "are used, in time order.",
                  "images");
    cli.addNote(
        "log.txt columns: image, location id, accepted loop id (0 none), highest hypothesis id, its value "
        "(loop-closure probability), WM size, vocabulary size, update time (ms, features excluded).\n"
        "detections.txt: `image matched_image value` per image, the highest hypothesis whether accepted or "
        "not, for `rtabmap-eval pr --threshold <Rtabmap/LoopThr>`.\n"
        "groundtruth.txt (datasets with ground truth): the pose of each image in image order (TUM), for "
        "`rtabmap-eval pr --gt`.\n"
        "Example: rtabmap-console --Rtabmap/TimeThr 700 --gt GT.png --json NewCollege/");
    if (auto exitCode = cli.parse(argc, argv)) return *exitCode;

    rtabmap::tools::console::ConsoleOptions options;
    options.inputs = cli.positionalList("inputs");
    options.outputDir = cli.option("output");
    options.groundTruthPath = cli.has("gt") ? cli.option("gt") : "";
    options.maxImages = cli.optionInt("max-images");
    options.format = cli.option("format");
    options.parameters = cli.parameters();
    options.progress = !cli.json();
    const auto report = rtabmap::tools::console::run(options);
    rtabmap::tools::console::printReport(report, std::cout);
    if (cli.json()) rtabmap::tools::printJsonLine(rtabmap::tools::console::toJson(report));
    return rtabmap::tools::kExitSuccess;
  });
}
