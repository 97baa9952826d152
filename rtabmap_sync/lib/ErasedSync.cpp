#include "ErasedSync.h"

#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>

#include <stdexcept>
#include <string>
#include <utility>

namespace rtabmap_sync::detail {

namespace {

using message_filters::NullType;
using NullPtr = boost::shared_ptr<NullType const>;

// Slot I of a synchroniser of N topics: a real message or message_filters' "unused" type.
template <size_t I, size_t N>
using SlotType = std::conditional_t<(I < N), ErasedMsg, NullType>;
template <size_t I, size_t N>
using SlotParam = const boost::shared_ptr<SlotType<I, N> const>&;

void collect(std::vector<ErasedPtr>& out, const ErasedPtr& m) { out.push_back(m); }
void collect(std::vector<ErasedPtr>&, const NullPtr&) {}

template <class Policy, size_t N, size_t... Is>
class SyncN : public ErasedSync {
 public:
  SyncN(const Policy& policy, const SetCallback& callback) : sync_(policy) {
    boost::function<void(SlotParam<Is, N>...)> cb = [callback](SlotParam<Is, N>... messages) {
      std::vector<ErasedPtr> set;
      set.reserve(N);
      (collect(set, messages), ...);
      callback(set);
    };
    sync_.registerCallback(cb);
  }

  void add(int slot, const ErasedPtr& message) override { (addIf<Is>(slot, message), ...); }

 private:
  template <size_t I>
  void addIf(int slot, const ErasedPtr& message) {
    if constexpr (I < N) {
      if (slot == int(I)) sync_.template add<I>(message);
    }
  }

  message_filters::Synchronizer<Policy> sync_;
};

template <size_t N, size_t... Is>
std::unique_ptr<ErasedSync> make(std::index_sequence<Is...>, bool approx, int queueSize, double maxInterval,
                                 const SetCallback& callback) {
  if (approx) {
    using Policy = message_filters::sync_policies::ApproximateTime<SlotType<Is, N>...>;
    Policy policy(static_cast<uint32_t>(queueSize));
    if (maxInterval > 0.0) policy.setMaxIntervalDuration(ros::Duration(maxInterval));
    return std::make_unique<SyncN<Policy, N, Is...>>(policy, callback);
  }
  using Policy = message_filters::sync_policies::ExactTime<SlotType<Is, N>...>;
  return std::make_unique<SyncN<Policy, N, Is...>>(Policy(static_cast<uint32_t>(queueSize)), callback);
}

}  // namespace

std::unique_ptr<ErasedSync> makeErasedSync(int count, bool approx, int queueSize, double maxInterval,
                                           const SetCallback& callback) {
  const auto all = std::make_index_sequence<9>();
  switch (count) {
    case 2: return make<2>(all, approx, queueSize, maxInterval, callback);
    case 3: return make<3>(all, approx, queueSize, maxInterval, callback);
    case 4: return make<4>(all, approx, queueSize, maxInterval, callback);
    case 5: return make<5>(all, approx, queueSize, maxInterval, callback);
    case 6: return make<6>(all, approx, queueSize, maxInterval, callback);
    case 7: return make<7>(all, approx, queueSize, maxInterval, callback);
    case 8: return make<8>(all, approx, queueSize, maxInterval, callback);
    case 9: return make<9>(all, approx, queueSize, maxInterval, callback);
    default: throw std::invalid_argument("makeErasedSync: " + std::to_string(count) + " topics (2 to 9 supported)");
  }
}

}  // namespace rtabmap_sync::detail
