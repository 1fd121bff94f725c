#pragma once
// Design-space search (docs/SWEEPS.md, "Search"): pagmo2's NSGA-II over a sweep's grid. A
// design is a vector of value indices, one integer gene per parameter; its fitness is the
// sweep's objectives (maximized ones negated) and its constraints as pagmo inequality
// constraints (metric - max <= 0, min - metric <= 0), turned into a death penalty by pagmo's
// `unconstrain` meta-problem (NSGA-II itself has no constraint handling). Each generation's
// designs are evaluated in one batch by the caller (in parallel, from the results database when
// a design was simulated before), then handed to pagmo from that cache. Deterministic for a
// seed: the designs, their order and the fitness are functions of the spec and the trace.
#include <cstddef>
#include <functional>
#include <vector>

#include "arch/sweep/sweep.hpp"

namespace edx::arch {

/// What the search needs of an evaluated design.
struct DesignFitness {
  std::vector<double> objectives;   ///< as the spec states them (maximized ones not negated)
  std::vector<double> constraints;  ///< the constraint metrics, in spec order
  bool feasible = true;             ///< within every constraint (the sweep's own verdict)
};

/// Evaluates designs given by grid index (SweepPoints::grid_index); returns one fitness per
/// index, in order. Throws to stop the search (the error is rethrown by run_nsga2).
using DesignEvaluator =
    std::function<std::vector<DesignFitness>(const std::vector<std::size_t>& grid_indices)>;

/// Runs NSGA-II (spec.population, spec.generations, spec.seed) over `points`' grid. Returns
/// the convergence table; the designs themselves are what `evaluate` saw.
std::vector<SearchGeneration> run_nsga2(const SweepSpec& spec, const SweepPoints& points,
                                        const DesignEvaluator& evaluate);

/// The hypervolume dominated by the non-dominated rows of `objectives` (minimization form:
/// maximized objectives negated by the caller) up to `reference` (pagmo::hypervolume); 0 when
/// there are none. Rows that do not dominate `reference` are left out.
double front_hypervolume(const std::vector<std::vector<double>>& objectives,
                         const std::vector<double>& reference);

/// The objectives of a design in minimization form, as the search and the hypervolume use them.
std::vector<double> minimization_form(const SweepSpec& spec, const std::vector<double>& objectives);

}  // namespace edx::arch
