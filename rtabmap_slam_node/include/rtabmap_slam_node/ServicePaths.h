#pragma once
// Which files a service request may touch (issue 10, item 5). A service such as load_database
// takes a path from anyone on the ROS graph and may create or delete that file (clear = true),
// so a request is confined to one directory the operator configured (the node's
// `database_directory`, by default the directory of `database_path`):
//  - a relative path is taken inside that directory;
//  - no ".." component at all, even one that would stay inside (it says the caller is probing);
//  - once every symbolic link along the way is resolved, the file must still be inside: a link
//    pointing out of the directory, or an absolute path elsewhere, is refused;
//  - the directory itself is not a file: refused.
// A refusal says why; nothing is touched.
//
// What this cannot stop: a process that can write into the directory and swaps a file for a
// symlink between this check and SQLite's open (a race the node cannot close without opening
// the file itself with O_NOFOLLOW). Keep that directory writable only by the robot's user.
#include <optional>
#include <string>

namespace rtabmap_slam_node {

// The directory services are confined to: `configured` when set (with "~/" expanded), else the
// directory of databasePath (the current directory when it has none). Returned canonical
// (symlinks resolved); nullopt and *why when that directory does not exist.
std::optional<std::string> serviceDirectory(const std::string& configured, const std::string& databasePath,
                                            std::string* why = nullptr);

// `requested` as a canonical path inside `directory` (itself canonical, from serviceDirectory),
// or nullopt and *why saying what was refused.
std::optional<std::string> confinedPath(const std::string& requested, const std::string& directory,
                                        std::string* why = nullptr);

}  // namespace rtabmap_slam_node
