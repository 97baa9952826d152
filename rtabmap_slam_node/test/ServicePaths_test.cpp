#include "rtabmap_slam_node/ServicePaths.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace rtabmap_slam_node {
namespace {
namespace fs = std::filesystem;

// A fresh tree per test: <root>/maps (the service directory), <root>/outside, <root>/maps2.
class ServicePathsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("service_paths_" + std::to_string(::getpid()) + "_" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_ / "maps" / "sub");
    fs::create_directories(root_ / "outside");
    fs::create_directories(root_ / "maps2");
    std::ofstream(root_ / "outside" / "precious.db") << "x";
    std::ofstream(root_ / "maps" / "map.db") << "x";
    dir_ = *serviceDirectory("", (root_ / "maps" / "map.db").string());
  }
  void TearDown() override { fs::remove_all(root_); }

  std::optional<std::string> confine(const std::string& p, std::string* why = nullptr) {
    return confinedPath(p, dir_, why);
  }

  fs::path root_;
  std::string dir_;
};

TEST_F(ServicePathsTest, DefaultDirectoryIsTheDatabasesOne) {
  EXPECT_EQ(dir_, fs::canonical(root_ / "maps").string());
  EXPECT_EQ(*serviceDirectory((root_ / "outside").string(), (root_ / "maps" / "map.db").string()),
            fs::canonical(root_ / "outside").string());
  std::string why;
  EXPECT_FALSE(serviceDirectory((root_ / "nowhere").string(), "", &why));
  EXPECT_NE(why.find("does not exist"), std::string::npos);
}

TEST_F(ServicePathsTest, RelativeAndAbsolutePathsInsideAreAccepted) {
  EXPECT_EQ(*confine("other.db"), dir_ + "/other.db");
  EXPECT_EQ(*confine("sub/new.db"), dir_ + "/sub/new.db");
  EXPECT_EQ(*confine((root_ / "maps" / "map.db").string()), dir_ + "/map.db");
  EXPECT_EQ(*confine("./map.db"), dir_ + "/map.db");
}

TEST_F(ServicePathsTest, DotDotIsRefusedEvenWhenItStaysInside) {
  std::string why;
  EXPECT_FALSE(confine("../outside/precious.db", &why));
  EXPECT_NE(why.find(".."), std::string::npos);
  EXPECT_FALSE(confine("sub/../map.db"));
  EXPECT_FALSE(confine((root_ / "maps" / ".." / "outside" / "precious.db").string()));
}

TEST_F(ServicePathsTest, AbsolutePathsElsewhereAreRefused) {
  std::string why;
  EXPECT_FALSE(confine((root_ / "outside" / "precious.db").string(), &why));
  EXPECT_NE(why.find("outside"), std::string::npos);
  EXPECT_FALSE(confine("/etc/passwd"));
  // A sibling whose name starts like the directory's is not inside it.
  EXPECT_FALSE(confine((root_ / "maps2" / "x.db").string()));
}

TEST_F(ServicePathsTest, SymlinksOutAreRefusedLinksInsideAreFollowed) {
  fs::create_symlink(root_ / "outside" / "precious.db", root_ / "maps" / "link.db");
  fs::create_directory_symlink(root_ / "outside", root_ / "maps" / "linkdir");
  fs::create_symlink(root_ / "outside" / "not_yet.db", root_ / "maps" / "dangling.db");
  fs::create_symlink(root_ / "maps" / "map.db", root_ / "maps" / "alias.db");
  std::string why;
  EXPECT_FALSE(confine("link.db", &why));
  EXPECT_NE(why.find("outside"), std::string::npos);
  EXPECT_FALSE(confine("linkdir/precious.db"));
  EXPECT_FALSE(confine("linkdir/new.db"));
  EXPECT_FALSE(confine("dangling.db", &why));
  EXPECT_NE(why.find("symbolic link"), std::string::npos);
  EXPECT_EQ(*confine("alias.db"), dir_ + "/map.db");
}

TEST_F(ServicePathsTest, EmptyAndDirectoriesAreRefused) {
  std::string why;
  EXPECT_FALSE(confine("", &why));
  EXPECT_NE(why.find("empty"), std::string::npos);
  EXPECT_FALSE(confine("sub", &why));
  EXPECT_NE(why.find("directory"), std::string::npos);
  EXPECT_FALSE(confine(".", &why));
  EXPECT_FALSE(confine(dir_));
}

}  // namespace
}  // namespace rtabmap_slam_node
