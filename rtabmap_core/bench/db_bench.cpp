// bench-db_bench: does the long-term memory stay fast as it grows?
//
// Fills a database with synthetic nodes shaped like RTAB-Map's (default 100,000 nodes of 500
// words), then prints:
//  - save time per node, median over the first and the last 1,000 nodes, and their ratio:
//    what the caller pays (queueing the node: the real-time update) and what the writer thread
//    pays (its transaction time divided by the nodes in it);
//  - load time of a random node by id (everything: words, links, sensor data), median at
//    1,000 nodes and at the end, and their ratio;
//  - bytes per node (file size / nodes).
// Human-readable lines first, then one JSON line with every figure.
//
// The synthetic node: 500 keypoints (640x480 image) with 32-byte binary descriptors (ORB-like),
// 3D points (one in ten unknown: NaN), a neighbour link to the previous node and a loop
// closure every 50 nodes to a random older node, a 160x120 JPEG image with its camera model.
// Vocabulary growth: a new place brings new words, fewer as the dictionary covers the
// environment: node n introduces max(25, 500 / (1 + n / 50)) new words (500 for the first
// node, 250 at n = 50, 25 from n = 950 on: about 2.5 million words at 100,000 nodes); its
// other keypoints reuse existing words, chosen uniformly.
//
// Usage: bench-db_bench [--nodes N] [--words W] [--dir DIR] [--keep]
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/db/Database.h"

namespace fs = std::filesystem;
using rtabmap::Link;
using rtabmap::Signature;
using rtabmap::Transform;
using rtabmap::db::Database;
using rtabmap::db::StoredWord;
using Clock = std::chrono::steady_clock;

namespace {

struct Settings {
  int nodes = 100000;
  int words = 500;
  std::string dir;
  bool keep = false;
  int pageSize = rtabmap::db::DatabaseOptions().pageSize;
};

void usage() {
  std::cerr << "usage: bench-db_bench [--nodes N] [--words W] [--dir DIR] [--keep]\n"
               "  --nodes N  nodes to write (default 100000; at least 2000)\n"
               "  --words W  words per node (default 500)\n"
               "  --dir DIR  where to put the database (default $TMPDIR or /var/tmp)\n"
               "  --keep     keep the database (default: deleted at the end)\n"
               "  --page-size B  SQLite page size of the new database (default: Database's)\n";
}

bool parse(int argc, char** argv, Settings& s) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool hasValue = i + 1 < argc;
    if (a == "--nodes" && hasValue) s.nodes = std::atoi(argv[++i]);
    else if (a == "--words" && hasValue) s.words = std::atoi(argv[++i]);
    else if (a == "--dir" && hasValue) s.dir = argv[++i];
    else if (a == "--page-size" && hasValue) s.pageSize = std::atoi(argv[++i]);
    else if (a == "--keep") s.keep = true;
    else return false;
  }
  return s.nodes >= 2000 && s.words > 0;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

double ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

// Fast deterministic random bytes (xorshift64): descriptors of 2.5 million words.
class Random {
 public:
  explicit Random(uint64_t seed) : state_(seed | 1) {}
  uint64_t next() {
    state_ ^= state_ << 13;
    state_ ^= state_ >> 7;
    state_ ^= state_ << 17;
    return state_;
  }
  float uniform() { return static_cast<float>(next() >> 40) / static_cast<float>(1 << 24); }
  void fill(unsigned char* data, size_t size) {
    for (size_t i = 0; i < size; i += 8) {
      const uint64_t r = next();
      std::memcpy(data + i, &r, std::min<size_t>(8, size - i));
    }
  }

 private:
  uint64_t state_;
};

int newWordsOf(int n, int words) {
  return std::min(words, std::max(words / 20, static_cast<int>(std::lround(words / (1.0 + n / 50.0)))));
}

// A small textured JPEG per "scene", shared by nodes: the image is not what is measured, but
// a node without one would make the database unrealistically small.
std::vector<rtabmap::Bytes> makeImages() {
  std::vector<rtabmap::Bytes> images;
  for (int k = 0; k < 8; ++k) {
    cv::Mat image(120, 160, CV_8UC3);
    for (int r = 0; r < image.rows; ++r)
      for (int c = 0; c < image.cols; ++c)
        image.at<cv::Vec3b>(r, c) = cv::Vec3b((r * 3 + k * 17) % 256, (c * 5 + k * 31) % 256, ((r ^ c) * 7) % 256);
    images.push_back(rtabmap::codec::compressImage(image, ".jpg"));
  }
  return images;
}

class NodeFactory {
 public:
  NodeFactory(int words, uint64_t seed) : words_(words), random_(seed), images_(makeImages()) {}

  // Node `id` (1-based) and the words it introduces.
  Signature make(int id, std::vector<StoredWord>* newWords) {
    const int n = id - 1;
    const int fresh = newWordsOf(n, words_);
    cv::Mat descriptors(words_, 32, CV_8UC1);
    random_.fill(descriptors.data, descriptors.total());
    std::multimap<int, int> wordIds;
    std::vector<cv::KeyPoint> keypoints(words_);
    std::vector<cv::Point3f> points(words_);
    newWords->clear();
    for (int i = 0; i < words_; ++i) {
      int wordId;
      if (i < fresh || lastWordId_ == 0) {
        wordId = ++lastWordId_;
        newWords->push_back(StoredWord{wordId, descriptors.row(i).clone()});
      } else {
        wordId = 1 + static_cast<int>(random_.next() % static_cast<uint64_t>(lastWordId_ - fresh));
      }
      wordIds.emplace(wordId, i);
      keypoints[i] = cv::KeyPoint{640 * random_.uniform(), 480 * random_.uniform(), 31.0f, 360 * random_.uniform(),
                                  random_.uniform(), static_cast<int>(random_.next() % 8)};  // braces: in order
      const float nan = std::numeric_limits<float>::quiet_NaN();
      points[i] = i % 10 == 0 ? cv::Point3f(nan, nan, nan)
                              : cv::Point3f{0.5f + 4 * random_.uniform(), random_.uniform() - 0.5f, random_.uniform()};
    }
    Signature node(id, 0, 0, 1000.0 + id, "", Transform(0.1 * id, 0.0, 0.0, 0.0, 0.0, 0.001 * id));
    node.setWords(wordIds, keypoints, points, descriptors);
    rtabmap::SensorData data(cv::Mat(), cv::Mat(), rtabmap::CameraModel(200.0, 200.0, 80.0, 60.0), id, node.stamp());
    data.setCompressed(images_[id % images_.size()], {}, {}, {});
    node.setSensorData(data);
    Link::InfMatrix information = Link::InfMatrix::Identity() * 1000.0;
    if (id > 1) node.addLink(Link(id, id - 1, Link::kNeighbor, Transform(-0.1, 0, 0, 0, 0, -0.001), information));
    if (id > 100 && id % 50 == 0) {
      const int old = 1 + static_cast<int>(random_.next() % static_cast<uint64_t>(id - 60));
      node.addLink(Link(id, old, Link::kGlobalClosure, Transform(0.2, 0.1, 0, 0, 0, 0.05), information));
    }
    return node;
  }

  int lastWordId() const { return lastWordId_; }

 private:
  int words_;
  Random random_;
  std::vector<rtabmap::Bytes> images_;
  int lastWordId_ = 0;
};

// Median time to load a random node (all parts) among 1..nodes.
double medianLoadMs(const Database& db, int nodes, int samples, uint64_t seed) {
  Random random(seed);
  std::vector<double> times;
  for (int i = 0; i < samples; ++i) {
    const int id = 1 + static_cast<int>(random.next() % static_cast<uint64_t>(nodes));
    const auto start = Clock::now();
    const std::optional<Signature> node = db.loadNode(id);
    times.push_back(ms(Clock::now() - start));
    if (!node || node->getWords().empty()) {
      throw std::runtime_error("node " + std::to_string(id) + " did not load");
    }
  }
  return median(times);
}

std::string defaultDir() {
  const char* tmp = std::getenv("TMPDIR");
  if (tmp && *tmp) return tmp;
  return fs::exists("/var/tmp") ? "/var/tmp" : fs::temp_directory_path().string();
}

}  // namespace

int main(int argc, char** argv) {
  Settings settings;
  if (!parse(argc, argv, settings)) {
    usage();
    return 2;
  }
  if (settings.dir.empty()) settings.dir = defaultDir();
  // About 40 kB of features and 3 kB of words per node at 500 words, plus the image.
  const double bytesPerNodeEstimate = settings.words * 90.0 + 6000.0;
  const double needed = bytesPerNodeEstimate * settings.nodes * 1.2;
  struct statvfs fsStat {};
  if (statvfs(settings.dir.c_str(), &fsStat) == 0) {
    const double available = static_cast<double>(fsStat.f_bavail) * fsStat.f_frsize;
    if (available < needed) {
      std::cerr << "bench-db_bench: " << settings.dir << " has " << available / 1e9 << " GB free, about "
                << needed / 1e9 << " GB are needed for " << settings.nodes << " nodes; use --dir or --nodes\n";
      return 1;
    }
  }
  const fs::path dir = fs::path(settings.dir) / ("rtabmap_db_bench_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / "bench.db").string();

  const int window = 1000;
  std::vector<double> callerMs(settings.nodes, 0.0);
  std::vector<double> writerMs(settings.nodes + 1, 0.0);
  std::mutex writerMutex;
  size_t commits = 0, committedNodes = 0;
  Database::Options options;
  options.maxPendingNodes = 0;  // the bench paces itself, outside the timed calls (below)
  options.pageSize = settings.pageSize;
  options.onCommitted = [&](const rtabmap::db::CommitInfo& commit) {
    if (commit.nodeIds.empty()) return;
    std::lock_guard<std::mutex> lock(writerMutex);
    const double perNode = commit.writeSeconds * 1000.0 / static_cast<double>(commit.nodeIds.size());
    for (int id : commit.nodeIds) writerMs[id] = perNode;
    ++commits;
    committedNodes += commit.nodeIds.size();
  };

  std::cout << "bench-db_bench: " << settings.nodes << " nodes of " << settings.words << " words into " << path
            << std::endl;
  const auto benchStart = Clock::now();
  double loadMsSmall = 0.0, loadMsLarge = 0.0;
  int words = 0;
  {
    Database db(path, options);
    NodeFactory factory(settings.words, 42);
    std::vector<StoredWord> newWords;
    for (int id = 1; id <= settings.nodes; ++id) {
      Signature node = factory.make(id, &newWords);
      // Keep a few hundred nodes queued at most: the robot adds one node per second, so a
      // real update never finds a long queue; here the loop runs far faster than that.
      while (db.writerStatus().pendingNodes > 256) std::this_thread::sleep_for(std::chrono::microseconds(200));
      const auto start = Clock::now();
      db.saveNode(std::move(node), std::move(newWords));
      callerMs[id - 1] = ms(Clock::now() - start);
      if (id == window) {
        db.flush();
        loadMsSmall = medianLoadMs(db, id, 500, 7);
      }
      if (id % 10000 == 0) {
        std::cerr << "  " << id << " nodes, " << factory.lastWordId() << " words, "
                  << db.sizeOnDisk() / 1e6 << " MB, " << std::chrono::duration<double>(Clock::now() - benchStart).count()
                  << " s" << std::endl;
      }
    }
    db.flush();
    loadMsLarge = medianLoadMs(db, settings.nodes, 500, 11);
    words = factory.lastWordId();
    db.close();
  }
  const double totalSeconds = std::chrono::duration<double>(Clock::now() - benchStart).count();
  const double fileBytes = static_cast<double>(fs::file_size(path));
  const double bytesPerNode = fileBytes / settings.nodes;

  const auto slice = [](const std::vector<double>& v, size_t begin, size_t end) {
    return std::vector<double>(v.begin() + static_cast<std::ptrdiff_t>(begin), v.begin() + static_cast<std::ptrdiff_t>(end));
  };
  const size_t n = static_cast<size_t>(settings.nodes);
  const double callerFirst = median(slice(callerMs, 0, window));
  const double callerLast = median(slice(callerMs, n - window, n));
  const double writerFirst = median(slice(writerMs, 1, window + 1));
  const double writerLast = median(slice(writerMs, n + 1 - window, n + 1));
  const double writerRatio = writerLast / writerFirst;
  const double callerRatio = callerLast / callerFirst;
  const double loadRatio = loadMsLarge / loadMsSmall;

  std::printf("nodes: %d, words per node: %d, vocabulary: %d words, %zu transactions (%.1f nodes each)\n",
              settings.nodes, settings.words, words, commits, commits ? double(committedNodes) / commits : 0.0);
  std::printf("save per node, caller (queueing):   first 1000 %.4f ms, last 1000 %.4f ms, ratio %.2f\n",
              callerFirst, callerLast, callerRatio);
  std::printf("save per node, writer thread:       first 1000 %.4f ms, last 1000 %.4f ms, ratio %.2f (goal <= 1.5)\n",
              writerFirst, writerLast, writerRatio);
  std::printf("load random node by id (all parts): at 1000 nodes %.4f ms, at %d nodes %.4f ms, ratio %.2f (goal <= 1.5)\n",
              loadMsSmall, settings.nodes, loadMsLarge, loadRatio);
  std::printf("bytes per node: %.0f (file %.1f MB)\n", bytesPerNode, fileBytes / 1e6);
  std::printf("total time: %.1f s\n", totalSeconds);
  std::printf(
      "{\"bench\":\"db\",\"nodes\":%d,\"words_per_node\":%d,\"vocabulary_words\":%d,"
      "\"save_caller_first_ms\":%.6f,\"save_caller_last_ms\":%.6f,\"save_caller_ratio\":%.4f,"
      "\"save_writer_first_ms\":%.6f,\"save_writer_last_ms\":%.6f,\"save_writer_ratio\":%.4f,"
      "\"load_small_ms\":%.6f,\"load_large_ms\":%.6f,\"load_ratio\":%.4f,"
      "\"bytes_per_node\":%.1f,\"file_bytes\":%.0f,\"total_seconds\":%.1f}\n",
      settings.nodes, settings.words, words, callerFirst, callerLast, callerRatio, writerFirst, writerLast,
      writerRatio, loadMsSmall, loadMsLarge, loadRatio, bytesPerNode, fileBytes, totalSeconds);
  std::fflush(stdout);

  if (settings.keep) {
    std::cerr << "kept " << path << std::endl;
  } else {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  return 0;
}
