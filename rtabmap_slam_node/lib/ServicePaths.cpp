#include "rtabmap_slam_node/ServicePaths.h"

#include <filesystem>
#include <system_error>

#include "rtabmap_slam_node/SlamNodeSupport.h"

namespace rtabmap_slam_node {
namespace fs = std::filesystem;

namespace {

void say(std::string* why, const std::string& text) {
  if (why) *why = text;
}

// Component-wise: "/a/bc" is not inside "/a/b".
bool isStrictlyInside(const fs::path& path, const fs::path& directory) {
  auto p = path.begin();
  for (auto d = directory.begin(); d != directory.end(); ++d, ++p) {
    if (d->empty()) continue;  // a trailing separator
    if (p == path.end() || *p != *d) return false;
  }
  return p != path.end() && !p->empty();
}

}  // namespace

std::optional<std::string> serviceDirectory(const std::string& configured, const std::string& databasePath,
                                            std::string* why) {
  fs::path directory;
  if (!configured.empty()) {
    directory = expandHome(configured);
  } else {
    directory = fs::path(databasePath).parent_path();
    if (directory.empty()) directory = fs::current_path();
  }
  std::error_code ec;
  const fs::path canonical = fs::canonical(directory, ec);
  if (ec || !fs::is_directory(canonical, ec)) {
    say(why, "the directory \"" + directory.string() + "\" does not exist");
    return std::nullopt;
  }
  return canonical.string();
}

std::optional<std::string> confinedPath(const std::string& requested, const std::string& directory,
                                        std::string* why) {
  if (requested.empty()) {
    say(why, "the path is empty");
    return std::nullopt;
  }
  const fs::path asked(requested);
  for (const fs::path& part : asked) {
    if (part == "..") {
      say(why, "\"" + requested + "\" contains \"..\"");
      return std::nullopt;
    }
  }
  // weakly_canonical resolves every symlink of the part that exists (the file itself when it
  // is a link), so a link out of the directory shows as a path outside it.
  const fs::path absolute = asked.is_absolute() ? asked : fs::path(directory) / asked;
  std::error_code ec;
  const fs::path resolved = fs::weakly_canonical(absolute, ec);
  if (ec) {
    say(why, "\"" + requested + "\" cannot be resolved: " + ec.message());
    return std::nullopt;
  }
  if (!isStrictlyInside(resolved, fs::path(directory))) {
    say(why, "\"" + requested + "\" resolves to \"" + resolved.string() + "\", outside \"" + directory +
                 "\" (services only touch files there: parameter database_directory)");
    return std::nullopt;
  }
  // weakly_canonical leaves a link whose target does not exist as it is; opening it would
  // create the target, wherever it points.
  if (fs::is_symlink(fs::symlink_status(resolved, ec))) {
    say(why, "\"" + requested + "\" is a symbolic link to a file that does not exist");
    return std::nullopt;
  }
  if (fs::is_directory(resolved, ec)) {
    say(why, "\"" + requested + "\" is a directory, not a database file");
    return std::nullopt;
  }
  return resolved.string();
}

}  // namespace rtabmap_slam_node
