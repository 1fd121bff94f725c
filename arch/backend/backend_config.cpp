#include "arch/backend/backend_config.hpp"

#include <yaml-cpp/yaml.h>

#include "arch/common/yaml_fields.hpp"

namespace edx::arch {

const FieldList<BackendConfig>& BackendConfig::fields() {
  using C = BackendConfig;
  const Bounds positive = Bounds::at_least(1);
  static const FieldList<C> list = {
      field("clock_mhz", &C::clock_mhz, "MHz", "backend clock (assumed: the frontend's HLS clock)",
            Bounds::above(0).at_most(1000)),
      field("gemm_block", &C::gemm_block, "",
            "b: the matrix-multiplication unit is a b x b systolic array (b^2 MACs a cycle)",
            positive.at_most(256)),
      field("decomp_block", &C::decomp_block, "",
            "b_d: the decomposition unit has b_d^2 multiply-accumulate lanes",
            positive.at_most(256)),
      field("inverse_lanes", &C::inverse_lanes, "", "multiply-accumulate lanes of the inverse unit",
            positive),
      field("transpose_words_per_cycle", &C::transpose_words_per_cycle, "words/cycle",
            "words the transpose unit moves a cycle", positive),
      field("trsv_lanes", &C::trsv_lanes, "", "multiply-accumulate lanes of the substitution unit",
            positive),
      field("divide_latency_cycles", &C::divide_latency_cycles, "cycles",
            "latency of the pipelined double-precision divider", positive),
      field("sqrt_latency_cycles", &C::sqrt_latency_cycles, "cycles",
            "latency of the pipelined square root", positive),
      choice_field("scalar_bytes", &C::scalar_bytes, "bytes", {"4", "8"},
                   "one matrix element in the units, the SPM and on the link: 8 double, 4 single "
                   "(also the precision of the units' MACs in the cost model)"),
      field("spm_bytes", &C::spm_bytes, "bytes", "the scratchpad holding the running op's operands",
            positive),
      field("symmetric_optimization", &C::symmetric_optimization, "",
            "compute and store only one triangle of symmetric results (Sec. VI-A)"),
      field("structured_inverse", &C::structured_inverse, "",
            "invert [A B; B^T D] with A diagonal and D 6x6 as reciprocals + a 6x6 inverse"),
      field("gemm_overlap_tiles", &C::gemm_overlap_tiles, "",
            "double-buffered accumulators: fill/drain paid once per op, not per tile"),
      field("blocked_solvers", &C::blocked_solvers, "",
            "blocked factorizations: trailing updates run on the multiplication array"),
      field("pose_dim", &C::pose_dim, "",
            "p: pose parameters of a marginalized keyframe, where the trace does not say",
            positive),
      field("landmark_dim", &C::landmark_dim, "",
            "l: parameters per marginalized landmark, where the trace does not say", positive),
  };
  return list;
}

void BackendConfig::validate() const { check_fields(*this, "backend", fields()); }

nlohmann::json BackendConfig::to_json() const { return fields_to_json(*this, fields()); }

BackendConfig BackendConfig::from_yaml(const YAML::Node& node, const std::string& where,
                                       const std::string& prefix) {
  return parse_section<BackendConfig>(node, where, prefix);
}

}  // namespace edx::arch
