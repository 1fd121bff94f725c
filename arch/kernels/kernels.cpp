#include "arch/kernels/kernels.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace edx::arch {

std::int64_t symmetric_elements(std::int64_t n, bool packed) {
  return packed ? n * (n + 1) / 2 : n * n;
}

std::optional<std::int64_t> detail_integer(const trace::KernelRecord& kernel, std::string_view key,
                                           std::int64_t min) {
  const nlohmann::json detail = nlohmann::json::parse(kernel.detail_json, nullptr, false);
  if (detail.is_discarded() || !detail.is_object()) {
    throw std::runtime_error(fmt::format("kernel '{}': detail: expected a JSON object, got '{}'",
                                         kernel.kernel, kernel.detail_json));
  }
  const auto it = detail.find(key);
  if (it == detail.end()) return std::nullopt;
  if (!it->is_number_integer() || it->get<std::int64_t>() < min) {
    throw std::runtime_error(
        fmt::format("kernel '{}': detail.{}: expected an integer >= {}, got {}", kernel.kernel, key,
                    min, it->dump()));
  }
  return it->get<std::int64_t>();
}

const std::vector<const AccelerableKernel*>& accelerable_kernels() {
  // The registry: one line per kernel.
  static const std::vector<const AccelerableKernel*> kernels = {
      &projection_kernel(),           &kalman_gain_kernel(),           &marginalization_kernel(),
      &schur_complement_kernel(),     &covariance_update_kernel(),     &gps_fusion_kernel(),
      &nullspace_projection_kernel(), &normal_equations_kernel(),      &solve_kernel(),
      &compression_kernel(),          &covariance_propagation_kernel()};
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
