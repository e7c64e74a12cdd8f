#pragma once
// The instruction sets Candela's SIMD kernels (Highway, dispatched at run time: restir/target_lanes.h,
// samplers/wide_importance.h) run with. Every kernel is compiled for the same list: SSSE3, SSE4, AVX2,
// AVX-512 (the files carry -march=x86-64-v2 so that the list does not depend on the build machine).
#include <functional>

namespace candela {

// The instruction set the kernels run with on this CPU (candela bench prints it).
const char* simd_target_name();
// Calls fn once per instruction set that both this CPU supports and the kernels were compiled for, with
// every kernel dispatched to it meanwhile (tests: every code path on one machine).
void for_each_simd_target(const std::function<void(const char* name)>& fn);

}  // namespace candela
