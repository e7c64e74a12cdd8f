#include "engine/simd_targets.h"

#include "hwy/highway.h"
#include "hwy/targets.h"

namespace candela {

const char* simd_target_name() {
  // The target the dispatch tables choose: the best one both compiled and supported.
  return hwy::TargetName(hwy::SupportedAndGeneratedTargets().front());
}

void for_each_simd_target(const std::function<void(const char* name)>& fn) {
  for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    fn(hwy::TargetName(target));
  }
  hwy::SetSupportedTargetsForTest(0);
}

}  // namespace candela
