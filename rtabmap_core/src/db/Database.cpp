#include "rtabmap_core/db/Database.h"

#include <chrono>
#include <deque>
#include <mutex>
#include <stdexcept>

#include "FileChecks.h"
#include "NodeLoad.h"
#include "NodeStore.h"
#include "Open.h"
#include "Overlay.h"
#include "Queries.h"
#include "Sqlite.h"
#include "Writer.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"

namespace rtabmap::db {

LoadOptions LoadOptions::withoutSensorData() {
  LoadOptions o;
  o.image = o.depthOrRight = o.scan = o.userData = o.grid = false;
  return o;
}

LoadOptions LoadOptions::nodeOnly() {
  LoadOptions o = withoutSensorData();
  o.links = o.words = o.wordDescriptors = false;
  return o;
}

// Two connections: the writer thread's (read-write) and the readers' (read-only). Separate
// connections rather than one behind a mutex, so that a load never waits for a transaction
// being written: under WAL a reader sees the last commit while the writer appends the next.
// The reader connection itself is shared by the caller threads under readMutex (a SQLite
// connection is not to be used by two threads at once).
class Database::Impl {
 public:
  std::string path;
  Options options;
  int schemaVersion = 0;
  int sessionId = -1;
  int sessionMapId = -1;
  std::unique_ptr<Writer> writer;
  mutable std::mutex readMutex;
  std::unique_ptr<Connection> reader;

  bool isOpen() const { return reader != nullptr; }

  void requireOpen() const {
    if (!reader) throw DatabaseError("the database is not open");
  }

  Writer& requireWriter() const {
    requireOpen();
    if (!writer) throw DatabaseError(path + ": opened read-only; nothing can be saved");
    return *writer;
  }

  Overlay snapshot() const { return writer ? Overlay(writer->pending()) : Overlay(); }

  void waitForWriter() const {
    if (writer) writer->waitIdle();
  }

  std::multimap<int, Link> linksOf(int id, const Overlay& overlay) const {
    size_t after = 0;
    std::multimap<int, Link> links;
    if (const SaveNodeOp* save = overlay.latestSave(id, &after)) {
      for (const auto& entry : save->node.getLinks()) {
        if (entry.second.type() != Link::kTemporary) links.insert(entry);
      }
    } else {
      std::lock_guard<std::mutex> lock(readMutex);
      links = load::links(*reader, id);
    }
    overlay.applyLinkChanges(id, links, after);
    return links;
  }

  std::optional<Signature> loadNode(int id, const LoadOptions& options, const Overlay& overlay) const {
    size_t after = 0;
    std::optional<Signature> node;
    if (const SaveNodeOp* save = overlay.latestSave(id, &after)) {
      node = filteredCopy(save->node, options);
    } else {
      std::lock_guard<std::mutex> lock(readMutex);
      // One read transaction: the node's rows come from one snapshot even if the writer
      // commits a new version of it between our statements.
      ReadTransaction snapshot(*reader);
      node = load::node(*reader, id, options);
    }
    if (!node) return node;
    overlay.applyNodeUpdates(*node, after);
    if (options.links && !overlay.empty()) {
      std::multimap<int, Link> links = node->getLinks();
      overlay.applyLinkChanges(id, links, after);
      node->removeLinks();
      for (const auto& entry : links) node->addLink(entry.second);
    }
    node->setSaved(true);
    node->setModified(false);
    node->setLinksModified(false);
    return node;
  }
};

Database::Database() : impl_(std::make_unique<Impl>()) {}

Database::Database(const std::string& path, const Options& options) : Database() { open(path, options); }

Database::~Database() {
  try {
    close();
  } catch (const std::exception& e) {
    RTABMAP_ERROR("closing the long-term memory: " << e.what());
  }
}

void Database::open(const std::string& path, const Options& options) {
  close();
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("Database::Options: " + why);
  auto impl = std::make_unique<Impl>();
  impl->path = path;
  impl->options = options;
  if (options.readOnly) {
    impl->reader = open::reader(path, options, true, &impl->schemaVersion);
  } else {
    std::unique_ptr<Connection> writer = open::writer(path, options, &impl->schemaVersion);
    // A new session continues after every map id already used.
    impl->sessionMapId = queries::maxMapId(*writer) + 1;
    impl->sessionId = store::insertSession(*writer, impl->sessionMapId, options.sessionParameters);
    impl->reader = open::reader(path, options, false, nullptr);
    Writer::Config config;
    config.maxBatchNodes = options.maxBatchNodes;
    config.maxPendingNodes = options.maxPendingNodes;
    config.imageFormat = options.imageFormat;
    config.onCommitted = options.onCommitted;
    impl->writer = std::make_unique<Writer>(std::move(writer), std::move(config));
  }
  impl_ = std::move(impl);
}

void Database::close() {
  if (!impl_->isOpen()) return;
  std::string error;
  if (impl_->writer) {
    try {
      const double now = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
      impl_->writer->enqueue(EndSessionOp{impl_->sessionId, now});
    } catch (const DatabaseError&) {
      // The writer failed: its error is reported below.
    }
    impl_->writer->stop();
    const WriterStatus status = impl_->writer->status();
    if (status.failed) {
      error = impl_->path + ": closed with " + std::to_string(status.pendingOperations) +
              " operations not written (the last node saved is " + std::to_string(status.lastDurableNodeId) +
              "): " + status.error;
    }
  }
  // The reader closes first: the last connection to close checkpoints the WAL into the file
  // and deletes it, which only the read-write one can do.
  impl_->reader.reset();
  impl_->writer.reset();
  impl_ = std::make_unique<Impl>();
  if (!error.empty()) throw DatabaseError(error);
}

bool Database::isOpen() const { return impl_->isOpen(); }
const std::string& Database::path() const { return impl_->path; }
bool Database::isReadOnly() const { return impl_->isOpen() && !impl_->writer; }
int Database::schemaVersion() const { return impl_->schemaVersion; }
int Database::sessionId() const { return impl_->sessionId; }
int Database::sessionMapId() const { return impl_->sessionMapId; }

// ------------------------------------------------------------------------------------ writes

uint64_t Database::saveNode(Signature node, std::vector<StoredWord> newWords) {
  Writer& writer = impl_->requireWriter();
  for (const auto& entry : node.getLinks()) {
    const Link& link = entry.second;
    if (link.type() != Link::kTemporary && link.transform().isNull()) {
      throw std::invalid_argument("node " + std::to_string(node.id()) + ": link " + std::to_string(link.from()) +
                                  "->" + std::to_string(link.to()) + " has a null transform and cannot be saved");
    }
  }
  return writer.enqueue(SaveNodeOp{std::move(node), std::move(newWords)});
}

uint64_t Database::saveWords(std::vector<StoredWord> words) {
  return impl_->requireWriter().enqueue(SaveWordsOp{std::move(words)});
}

uint64_t Database::saveLink(const Link& link) {
  Writer& writer = impl_->requireWriter();
  if (link.type() == Link::kTemporary || link.type() == Link::kUndef || link.transform().isNull()) {
    throw std::invalid_argument("link " + std::to_string(link.from()) + "->" + std::to_string(link.to()) +
                                " cannot be saved: " +
                                (link.transform().isNull() ? std::string("null transform")
                                                           : "type " + link.typeName() + " is never saved"));
  }
  return writer.enqueue(SaveLinkOp{link});
}

uint64_t Database::removeLink(int from, int to, Link::Type type) {
  return impl_->requireWriter().enqueue(RemoveLinkOp{from, to, type});
}

uint64_t Database::updateNode(const NodeUpdate& update) {
  return impl_->requireWriter().enqueue(UpdateNodeOp{update});
}

uint64_t Database::saveStatistics(const StoredStatistics& statistics) {
  return impl_->requireWriter().enqueue(SaveStatisticsOp{statistics});
}

uint64_t Database::setSessionParameters(const std::string& parameters) {
  return impl_->requireWriter().enqueue(SessionParametersOp{impl_->sessionId, parameters});
}

void Database::flush() {
  if (impl_->writer) impl_->writer->flush();
}

WriterStatus Database::writerStatus() const {
  return impl_->writer ? impl_->writer->status() : WriterStatus();
}

int Database::lastDurableNodeId() const { return writerStatus().lastDurableNodeId; }

// --------------------------------------------------------------------------- per-node reads

std::optional<Signature> Database::loadNode(int id, const LoadOptions& options) const {
  impl_->requireOpen();
  return impl_->loadNode(id, options, impl_->snapshot());
}

std::vector<Signature> Database::loadNodes(const std::vector<int>& ids, const LoadOptions& options) const {
  impl_->requireOpen();
  const Overlay overlay = impl_->snapshot();
  std::vector<Signature> nodes;
  nodes.reserve(ids.size());
  for (int id : ids) {
    if (std::optional<Signature> node = impl_->loadNode(id, options, overlay)) nodes.push_back(std::move(*node));
  }
  return nodes;
}

std::multimap<int, Link> Database::loadLinks(int id) const {
  impl_->requireOpen();
  return impl_->linksOf(id, impl_->snapshot());
}

std::map<int, int> Database::neighborIds(int id, int maxDepth) const {
  impl_->requireOpen();
  const Overlay overlay = impl_->snapshot();
  std::map<int, int> depths;
  {
    // The start node must exist (in the file or queued).
    size_t after = 0;
    if (!overlay.latestSave(id, &after)) {
      std::lock_guard<std::mutex> lock(impl_->readMutex);
      if (!load::node(*impl_->reader, id, LoadOptions::nodeOnly())) return depths;
    }
  }
  // Breadth-first over the links, so each node gets its smallest depth.
  std::deque<int> frontier{id};
  depths[id] = 0;
  while (!frontier.empty()) {
    const int current = frontier.front();
    frontier.pop_front();
    if (depths[current] >= maxDepth) continue;
    for (const auto& [other, link] : impl_->linksOf(current, overlay)) {
      if (other <= 0 || other == current || depths.count(other)) continue;
      depths[other] = depths[current] + 1;
      frontier.push_back(other);
    }
  }
  return depths;
}

std::vector<Signature> Database::loadNeighbors(int id, int maxDepth, const LoadOptions& options) const {
  std::vector<int> ids;
  for (const auto& entry : neighborIds(id, maxDepth)) ids.push_back(entry.first);
  return loadNodes(ids, options);
}

std::vector<StoredWord> Database::loadWords(const std::vector<int>& ids) const {
  impl_->requireOpen();
  const Overlay overlay = impl_->snapshot();
  std::vector<StoredWord> words;
  words.reserve(ids.size());
  std::lock_guard<std::mutex> lock(impl_->readMutex);
  // One read transaction for the batch (a retrieval's missing words): SQLite would otherwise
  // open and close one per statement.
  ReadTransaction snapshot(*impl_->reader);
  for (int id : ids) {
    std::optional<StoredWord> word = overlay.word(id);
    if (!word) word = load::word(*impl_->reader, id);
    if (word) words.push_back(std::move(*word));
  }
  return words;
}

std::optional<StoredStatistics> Database::loadStatistics(int nodeId) const {
  impl_->requireOpen();
  const Overlay overlay = impl_->snapshot();
  if (std::optional<StoredStatistics> queued = overlay.statistics(nodeId)) return queued;
  std::lock_guard<std::mutex> lock(impl_->readMutex);
  return load::statistics(*impl_->reader, nodeId);
}

int Database::lastNodeId() const {
  impl_->requireOpen();
  const Overlay overlay = impl_->snapshot();
  std::lock_guard<std::mutex> lock(impl_->readMutex);
  return std::max(overlay.maxNodeId(), queries::maxNodeId(*impl_->reader));
}

int Database::lastWordId() const {
  impl_->requireOpen();
  const Overlay overlay = impl_->snapshot();
  std::lock_guard<std::mutex> lock(impl_->readMutex);
  return std::max(overlay.maxWordId(), queries::maxWordId(*impl_->reader));
}

int Database::lastMapId() const {
  impl_->requireOpen();
  const Overlay overlay = impl_->snapshot();
  std::lock_guard<std::mutex> lock(impl_->readMutex);
  return std::max(overlay.maxMapId(), queries::maxMapId(*impl_->reader));
}

// --------------------------------------------------------------------- whole-database reads

std::vector<int> Database::nodeIds() const {
  impl_->requireOpen();
  impl_->waitForWriter();
  std::lock_guard<std::mutex> lock(impl_->readMutex);
  return queries::nodeIds(*impl_->reader);
}

std::vector<int> Database::intermediateNodeIds() const {
  impl_->requireOpen();
  impl_->waitForWriter();
  std::lock_guard<std::mutex> lock(impl_->readMutex);
  return queries::intermediateNodeIds(*impl_->reader);
}

std::map<int, Signature> Database::loadAllNodeHeaders() const {
  impl_->requireOpen();
  impl_->waitForWriter();
  std::lock_guard<std::mutex> lock(impl_->readMutex);
  return queries::nodeHeaders(*impl_->reader);
}

std::multimap<int, Link> Database::loadAllLinks(bool bothDirections) const {
  impl_->requireOpen();
  impl_->waitForWriter();
  std::lock_guard<std::mutex> lock(impl_->readMutex);
  return queries::allLinks(*impl_->reader, bothDirections);
}

std::map<int, std::string> Database::labels() const {
  impl_->requireOpen();
  impl_->waitForWriter();
  std::lock_guard<std::mutex> lock(impl_->readMutex);
  return queries::labels(*impl_->reader);
}

std::vector<SessionInfo> Database::sessions() const {
  impl_->requireOpen();
  impl_->waitForWriter();
  std::lock_guard<std::mutex> lock(impl_->readMutex);
  return queries::sessions(*impl_->reader);
}

std::string Database::lastSessionParameters() const {
  const std::vector<SessionInfo> all = sessions();
  return all.empty() ? std::string() : all.back().parameters;
}

DatabaseSummary Database::summary() const {
  impl_->requireOpen();
  impl_->waitForWriter();
  std::lock_guard<std::mutex> lock(impl_->readMutex);
  ReadTransaction snapshot(*impl_->reader);
  return queries::summary(*impl_->reader);
}

ConsistencyReport Database::checkConsistency(bool full) const {
  impl_->requireOpen();
  impl_->waitForWriter();
  std::lock_guard<std::mutex> lock(impl_->readMutex);
  ReadTransaction snapshot(*impl_->reader);
  return queries::consistency(*impl_->reader, full);
}

int64_t Database::sizeOnDisk() const { return files::sizeOnDisk(impl_->path); }

}  // namespace rtabmap::db
