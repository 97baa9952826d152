#pragma once
// The write operations queued for the writer thread. Each is immutable once queued (readers
// look at queued operations while the writer writes them) and has "set" semantics: applying
// one twice leaves the same state as applying it once, which is what lets a reader overlay
// queued operations on a database snapshot that may already contain some of them.
#include <cstdint>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "rtabmap_core/db/Types.h"
#include "rtabmap_core/memory/Link.h"
#include "rtabmap_core/memory/Signature.h"

namespace rtabmap::db {

struct SaveNodeOp {
  Signature node;
  std::vector<StoredWord> words;  // words this node introduced into the dictionary
};
struct SaveWordsOp {
  std::vector<StoredWord> words;
};
struct SaveLinkOp {
  Link link;
};
struct RemoveLinkOp {
  int from = 0;
  int to = 0;
  Link::Type type = Link::kUndef;
};
struct UpdateNodeOp {
  NodeUpdate update;
};
struct SaveStatisticsOp {
  StoredStatistics statistics;
};
struct SessionParametersOp {
  int sessionId = 0;
  std::string parameters;
};
struct EndSessionOp {
  int sessionId = 0;
  double endTime = 0.0;
};

struct Operation {
  uint64_t ticket = 0;
  std::variant<SaveNodeOp, SaveWordsOp, SaveLinkOp, RemoveLinkOp, UpdateNodeOp, SaveStatisticsOp,
               SessionParametersOp, EndSessionOp>
      op;
};

using OperationPtr = std::shared_ptr<const Operation>;

}  // namespace rtabmap::db
