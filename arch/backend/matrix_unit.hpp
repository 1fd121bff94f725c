#pragma once
// A backend matrix unit (paper Sec. VI-A, Table II, Fig. 14): one interface, its implementations
// beside it in arch/backend/units/ (one file each, registered there by name), and the platform's
// instances of them (`backend.units`, docs/CONFIG.md). A unit kind owns its parameters, the
// cycles of each trace op it serves, the scratchpad scalars of their operands, its LUT/FF/DSP/BRAM
// and its MAC lanes (energy); the backend (BackendConfig) holds the instances and what they share
// (clock, scratchpad, scalar format, the symmetric-S optimization).
//
//   backend:
//     units:
//       gemm:          {kind: systolic_array, block: 4, overlap_tiles: true}
//       decomposition: {kind: decomposition, block: 1, blocked: true}
//       ...
//
// Every trace op is served by at most one instance; `count` identical copies of an instance share
// an op's work (Amdahl: the part of it that splits over copies, per kind) and are a pool the DES
// grants first come, first served. An op no instance serves cannot be offloaded: the kernels
// holding it stay on the host.
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "arch/common/registry.hpp"
#include "arch/cost/resources.hpp"
#include "common/config_fields.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch {

struct BackendConfig;

/// Scalars an op reads (its operands) and writes (its result) at least once, stored as the
/// backend stores them (op_timing.hpp: op_operand_scalars).
struct OperandScalars {
  std::int64_t in = 0, out = 0;
};

class MatrixUnit : public Component {
 public:
  static constexpr const char* kKindName = "backend matrix unit";
  /// True for the trace ops it serves.
  virtual bool serves(trace::Op op) const = 0;
  /// Table II's building block, for reports ("matrix multiplication (b x b array)").
  virtual std::string building_block() const = 0;
  /// Cycles of `op` (one it serves) on `copies` idle copies of this unit sharing its work, in
  /// `backend` (its shared parameters, and the other units for blocked algorithms). 0 for an op
  /// with a zero dimension.
  virtual std::int64_t cycles(const trace::OpRecord& op, int copies,
                              const BackendConfig& backend) const = 0;
  /// Cycles of op.batch independent instances of `op` on `copies` copies. By default
  /// min(b · cycles(op, c), ⌈b / c⌉ · cycles(op, 1)): all copies on each instance, or one
  /// instance a copy in rounds, whichever is shorter; a kind that streams instances overrides it
  /// (the systolic array: their tiles as one op's).
  virtual std::int64_t batch_cycles(const trace::OpRecord& op, int copies,
                                    const BackendConfig& backend) const;
  /// Multiply-accumulate lanes of one copy: a busy cycle is this many MACs (energy; 0: none).
  virtual double mac_lanes() const = 0;
  /// LUT, FF, DSP and BRAM of one copy with MACs of `arithmetic`.
  virtual cost::Resources resources(cost::Arithmetic arithmetic) const = 0;
  /// The b x b output tile of an array (blocked solvers block at it); 0 for other units.
  virtual int tile() const { return 0; }
  /// The scalars `op` keeps in the scratchpad, in and out, when this unit stores them its own way
  /// (the structured inverse keeps A_mm as its blocks); nullopt: the op's generic storage.
  virtual std::optional<OperandScalars> own_operands(const trace::OpRecord&,
                                                     const BackendConfig&) const {
    return std::nullopt;
  }
  /// Multiply-adds of `op` when this unit computes it its own way (fewer than the generic
  /// count); nullopt: op_timing's generic count.
  virtual std::optional<std::int64_t> own_macs(const trace::OpRecord&, const BackendConfig&) const {
    return std::nullopt;
  }
};

/// LUT, FF, DSP and BRAM of a factorization datapath (decomposition, householder): `lanes` MACs
/// of `arithmetic` with two operand registers each, one square root, one divider, an address
/// generator.
cost::Resources factorization_datapath(double lanes, cost::Arithmetic arithmetic);

/// One instance of a unit kind in a platform: `backend.units.<name>`.
struct MatrixUnitInstance {
  std::string name;                        ///< its key under backend.units ("gemm")
  std::shared_ptr<const MatrixUnit> unit;  ///< the kind, with its parameters
  /// Identical copies; 0 leaves the instance out of the design (its ops stay on the host).
  int count = 1;
  double clock_mhz = 0;  ///< its clock; 0: the backend's (backend.clock_mhz)
  /// Its arithmetic: the backend's (backend.precision; one for every unit, as the trace has one).
  trace::Precision precision = trace::Precision::kFp64;

  cost::Arithmetic arithmetic() const;
  /// The keys every instance has besides `kind` and its kind's own (docs/CONFIG.md).
  static const FieldList<MatrixUnitInstance>& fields();
  nlohmann::json to_json() const;  ///< kind, instance keys and the kind's parameters
};

/// The instance `kind` with its default parameters (code that builds a backend without YAML).
MatrixUnitInstance make_matrix_unit(std::string name, std::string_view kind, int count = 1);
/// The same with `params` (YAML text of the kind's keys, e.g. "{block: 8}") over its defaults.
MatrixUnitInstance make_matrix_unit(std::string name, std::string_view kind,
                                    const std::string& params, int count = 1);

}  // namespace edx::arch
