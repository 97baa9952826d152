#pragma once
// What a read sees of the operations still queued for the writer. A read takes a snapshot of
// the queue FIRST, then reads the file, then overlays the snapshot: an operation committed in
// between is then found in both, which is harmless because operations are idempotent "sets"
// (Operations.h), and none can be missed (it is in the file or in the snapshot).
#include <map>
#include <optional>
#include <vector>

#include "Operations.h"

namespace rtabmap::db {

class Overlay {
 public:
  Overlay() = default;
  explicit Overlay(std::vector<OperationPtr> queued) : queued_(std::move(queued)) {}

  bool empty() const { return queued_.empty(); }

  // The most recent queued save of this node; *after is the index following it (the
  // operations to overlay on it). nullptr if none queued: overlay all, from index 0.
  const SaveNodeOp* latestSave(int id, size_t* after) const;
  // Weight, label and pose updates queued from `after` on.
  void applyNodeUpdates(Signature& node, size_t after) const;
  // Link additions and removals touching node `id` queued from `after` on, applied to the
  // links stored from it.
  void applyLinkChanges(int id, std::multimap<int, Link>& links, size_t after) const;
  std::optional<StoredWord> word(int id) const;
  std::optional<StoredStatistics> statistics(int nodeId) const;
  int maxNodeId() const;
  int maxWordId() const;
  int maxMapId() const;

 private:
  std::vector<OperationPtr> queued_;
};

// A copy of a queued node reduced to the parts a load asked for, as if read from the file.
Signature filteredCopy(const Signature& node, const LoadOptions& options);

}  // namespace rtabmap::db
