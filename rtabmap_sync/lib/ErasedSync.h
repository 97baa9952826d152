#pragma once
// message_filters policies over type-erased messages. The policies only need a stamp per
// message, so every topic is fed as an ErasedMsg (stamp + the typed message behind a void
// pointer) and the synchroniser is instantiated once per topic count (2..9) instead of once
// per combination of message types.
#include <ros/message_traits.h>
#include <ros/time.h>

#include <boost/shared_ptr.hpp>
#include <functional>
#include <memory>
#include <vector>

namespace rtabmap_sync::detail {

struct ErasedMsg {
  ros::Time stamp;
  boost::shared_ptr<void const> message;
};
using ErasedPtr = boost::shared_ptr<ErasedMsg const>;

class ErasedSync {
 public:
  virtual ~ErasedSync() = default;
  // Feeds one message of topic `slot` (0-based, < the count given to makeErasedSync).
  virtual void add(int slot, const ErasedPtr& message) = 0;
};

using SetCallback = std::function<void(const std::vector<ErasedPtr>&)>;

// count in [2, 9]. approx: ApproximateTime (maxInterval > 0 bounds a set's stamp spread),
// else ExactTime. The callback gets one message per slot, in slot order.
std::unique_ptr<ErasedSync> makeErasedSync(int count, bool approx, int queueSize, double maxInterval,
                                           const SetCallback& callback);

}  // namespace rtabmap_sync::detail

namespace ros::message_traits {
template <>
struct TimeStamp<rtabmap_sync::detail::ErasedMsg> {
  static ros::Time value(const rtabmap_sync::detail::ErasedMsg& m) { return m.stamp; }
  static ros::Time* pointer(rtabmap_sync::detail::ErasedMsg& m) { return &m.stamp; }
  static ros::Time const* pointer(const rtabmap_sync::detail::ErasedMsg& m) { return &m.stamp; }
};
}  // namespace ros::message_traits
