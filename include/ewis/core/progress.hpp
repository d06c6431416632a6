#pragma once
// Algorithms never print (DESIGN.md); long ones report through this optional callback.
#include <functional>
#include <string_view>

namespace ewis {

// stage: a short name ("filter", "register"); fraction in [0, 1].
using ProgressFn = std::function<void(std::string_view stage, double fraction)>;

}  // namespace ewis
