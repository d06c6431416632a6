#pragma once
// Shared by the three step programs: a monotonic timer and the one-line JSON they print.
#include <chrono>
#include <cstdio>
#include <string>

namespace steps {

struct Timer {
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  double ms() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
};

// {"step": ..., "ms": ..., "result": ..., "detail": "..."}: `result` is the number compared for agreement.
inline void print(const std::string& step, double ms, double result, const std::string& detail = "") {
  std::printf("{\"step\": \"%s\", \"ms\": %.3f, \"result\": %.6f, \"detail\": \"%s\"}\n", step.c_str(), ms, result,
              detail.c_str());
}

inline int usage(const char* prog) {
  std::fprintf(stderr,
               "usage: %s read FILE | resolution FILE | ror FILE RADIUS K | voxel FILE LEAF | cluster FILE TOL |"
               " sample MESH N | icp SOURCE TARGET POSE\n",
               prog);
  return 2;
}

}  // namespace steps
