#include "arch/kernels/kernels.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace edx::arch {

std::int64_t symmetric_elements(std::int64_t n, bool packed) {
  return packed ? n * (n + 1) / 2 : n * n;
}

const std::vector<const AccelerableKernel*>& accelerable_kernels() {
  // The registry: one line per kernel.
  static const std::vector<const AccelerableKernel*> kernels = {
      &projection_kernel(),       &kalman_gain_kernel(),       &marginalization_kernel(),
      &schur_complement_kernel(), &covariance_update_kernel(), &gps_fusion_kernel(),
      &nullspace_projection_kernel()};
  return kernels;
}

std::vector<std::string> paper_offload_set() {
  return {"projection", "kalman_gain", "marginalization"};
}

const AccelerableKernel* find_accelerable_kernel(std::string_view name) {
  for (const AccelerableKernel* k : accelerable_kernels()) {
    if (k->name == name) return k;
  }
  return nullptr;
}

std::string accelerable_kernel_names() {
  const auto& kernels = accelerable_kernels();
  std::string text;
  for (std::size_t i = 0; i < kernels.size(); ++i) {
    if (i > 0) text += i + 1 == kernels.size() ? " or " : ", ";
    text += kernels[i]->name;
  }
  return text;
}

const AccelerableKernel& accelerable_kernel(std::string_view name) {
  if (const AccelerableKernel* k = find_accelerable_kernel(name)) return *k;
  throw std::runtime_error(fmt::format("kernel '{}': expected an accelerable kernel ({})", name,
                                       accelerable_kernel_names()));
}

}  // namespace edx::arch
