#include "cli/bag_topic_args.h"

#include "rawlog/sequence_source.h"

namespace dynslam::cli {

BagTopics BagTopicArgs::value() { return {rgb_.getValue(), depth_.getValue(), info_.getValue()}; }

}  // namespace dynslam::cli
