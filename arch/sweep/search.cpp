#include "arch/sweep/search.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <pagmo/algorithms/nsga2.hpp>
#include <pagmo/bfe.hpp>
#include <pagmo/population.hpp>
#include <pagmo/problem.hpp>
#include <pagmo/problems/unconstrain.hpp>
#include <pagmo/utils/hypervolume.hpp>
#include <stdexcept>

namespace edx::arch {
namespace {

/// Stands in for a metric that is not a finite number (pagmo needs finite fitness).
constexpr double kHuge = 1e300;

double finite(double v) { return std::isfinite(v) ? v : kHuge; }

/// The evaluated designs of one search, shared by the problem's copies.
struct SearchState {
  const SweepSpec* spec = nullptr;
  const SweepPoints* points = nullptr;
  DesignEvaluator evaluate;
  std::mutex mutex;
  std::map<std::size_t, pagmo::vector_double> fitness;  ///< pagmo fitness by grid index
  std::vector<std::size_t> order;                       ///< grid indices, first evaluation first
  std::vector<std::vector<double>> minimized;           ///< objectives (min form), by `order`
  std::vector<bool> feasible;                           ///< by `order`

  /// The parameters with two or more values: one gene each (a fixed one has no gene).
  std::vector<std::size_t> genes;

  std::size_t index_of(const pagmo::vector_double& x) const {
    std::vector<std::size_t> choice(spec->parameters.size(), 0);
    for (std::size_t g = 0; g < x.size(); ++g) choice[genes[g]] = std::size_t(std::llround(x[g]));
    return points->grid_index(choice);
  }

  /// Evaluates the designs not seen yet, in one batch, and caches their pagmo fitness:
  /// [objectives (min form), constraints (<= 0 satisfied)].
  void prefetch(const std::vector<std::size_t>& indices) {
    std::vector<std::size_t> todo;
    {
      std::lock_guard<std::mutex> lock(mutex);
      for (std::size_t i : indices) {
        if (!fitness.contains(i) && std::find(todo.begin(), todo.end(), i) == todo.end()) {
          todo.push_back(i);
        }
      }
    }
    if (todo.empty()) return;
    const std::vector<DesignFitness> results = evaluate(todo);
    std::lock_guard<std::mutex> lock(mutex);
    for (std::size_t k = 0; k < todo.size(); ++k) {
      const DesignFitness& r = results.at(k);
      const std::vector<double> objectives = minimization_form(*spec, r.objectives);
      pagmo::vector_double f;
      for (double v : objectives) f.push_back(finite(v));
      for (std::size_t c = 0; c < spec->constraints.size(); ++c) {
        const SweepConstraint& con = spec->constraints[c];
        const double v = finite(r.constraints.at(c));
        if (con.upper() < 1e300) f.push_back(v - con.upper());
        if (con.lower() > -1e300) f.push_back(con.lower() - v);
      }
      fitness.emplace(todo[k], f);
      order.push_back(todo[k]);
      minimized.push_back(objectives);
      feasible.push_back(r.feasible);
    }
  }

  pagmo::vector_double fitness_of(std::size_t index) {
    prefetch({index});
    std::lock_guard<std::mutex> lock(mutex);
    return fitness.at(index);
  }
};

std::size_t constraint_count(const SweepSpec& spec) {
  std::size_t n = 0;
  for (const SweepConstraint& c : spec.constraints) n += (c.upper() < 1e300) + (c.lower() > -1e300);
  return n;
}

/// The sweep's grid as a pagmo problem: one integer gene per parameter (its value index).
struct GridProblem {
  std::shared_ptr<SearchState> state;

  pagmo::vector_double fitness(const pagmo::vector_double& x) const {
    return state->fitness_of(state->index_of(x));
  }
  std::pair<pagmo::vector_double, pagmo::vector_double> get_bounds() const {
    pagmo::vector_double lower, upper;
    for (std::size_t p : state->genes) {
      lower.push_back(0);
      upper.push_back(double(state->spec->parameters[p].size() - 1));
    }
    return {lower, upper};
  }
  pagmo::vector_double::size_type get_nobj() const { return state->spec->objectives.size(); }
  pagmo::vector_double::size_type get_nic() const { return constraint_count(*state->spec); }
  pagmo::vector_double::size_type get_nix() const { return state->genes.size(); }
  std::string get_name() const { return "edx sweep grid"; }
  pagmo::thread_safety get_thread_safety() const { return pagmo::thread_safety::none; }
};

/// Batch evaluation: a generation's designs are evaluated together (the caller's thread pool),
/// then pagmo's own fitness (through `unconstrain`'s penalty) is taken of each from the cache.
struct PrefetchBfe {
  std::shared_ptr<SearchState> state;
  pagmo::vector_double operator()(const pagmo::problem& p, const pagmo::vector_double& dvs) const {
    const std::size_t n = p.get_nx();
    std::vector<std::size_t> indices;
    for (std::size_t i = 0; i + n <= dvs.size(); i += n) {
      indices.push_back(
          state->index_of(pagmo::vector_double(dvs.begin() + long(i), dvs.begin() + long(i + n))));
    }
    state->prefetch(indices);
    pagmo::vector_double out;
    for (std::size_t i = 0; i + n <= dvs.size(); i += n) {
      const pagmo::vector_double f =
          p.fitness(pagmo::vector_double(dvs.begin() + long(i), dvs.begin() + long(i + n)));
      out.insert(out.end(), f.begin(), f.end());
    }
    return out;
  }
  std::string get_name() const { return "edx batch evaluation"; }
  pagmo::thread_safety get_thread_safety() const { return pagmo::thread_safety::none; }
};

std::vector<SearchGeneration> evolve(const SweepSpec& spec,
                                     const std::shared_ptr<SearchState>& state);

}  // namespace

std::vector<double> minimization_form(const SweepSpec& spec,
                                      const std::vector<double>& objectives) {
  std::vector<double> out(objectives.size());
  for (std::size_t i = 0; i < objectives.size(); ++i) {
    out[i] = spec.objectives.at(i).maximize ? -objectives[i] : objectives[i];
  }
  return out;
}

double front_hypervolume(const std::vector<std::vector<double>>& objectives,
                         const std::vector<double>& reference) {
  std::vector<pagmo::vector_double> inside;
  for (const std::vector<double>& row : objectives) {
    bool dominated_by_reference = true;
    for (std::size_t i = 0; i < row.size(); ++i) {
      dominated_by_reference = dominated_by_reference && row[i] < reference[i];
    }
    if (dominated_by_reference) inside.push_back(row);
  }
  if (inside.empty()) return 0;
  if (reference.size() == 1) {  // one objective: the distance of the best to the reference
    double best = inside.front()[0];
    for (const auto& row : inside) best = std::min(best, row[0]);
    return reference[0] - best;
  }
  std::vector<pagmo::vector_double> nd;
  for (std::size_t i : pareto_front(inside, std::vector<bool>(reference.size(), false))) {
    nd.push_back(inside[i]);
  }
  return pagmo::hypervolume(nd, true).compute(reference);
}

std::vector<SearchGeneration> run_nsga2(const SweepSpec& spec, const SweepPoints& points,
                                        const DesignEvaluator& evaluate) {
  if (!spec.nsga2) throw std::logic_error("run_nsga2: the spec's sampling is not nsga2");
  auto state = std::make_shared<SearchState>();
  state->spec = &spec;
  state->points = &points;
  state->evaluate = evaluate;
  for (std::size_t p = 0; p < spec.parameters.size(); ++p) {
    if (spec.parameters[p].size() > 1) state->genes.push_back(p);
  }
  if (state->genes.empty()) {
    throw std::runtime_error(fmt::format(
        "{}: sampling.nsga2: every parameter has one value: nothing to search (use grid)",
        spec.file));
  }
  try {
    return evolve(spec, state);
  } catch (const std::invalid_argument& e) {
    // pagmo's own errors are several lines ("function: ...\nwhere: ...\nwhat: ..."): keep
    // the "what".
    std::string what = e.what();
    if (const auto at = what.find("what: "); at != std::string::npos) what = what.substr(at + 6);
    while (!what.empty() && (what.back() == '\n' || what.back() == ' ')) what.pop_back();
    std::replace(what.begin(), what.end(), '\n', ' ');
    throw std::runtime_error(fmt::format("{}: sampling.nsga2: pagmo: {}", spec.file, what));
  }
}

namespace {

std::vector<SearchGeneration> evolve(const SweepSpec& spec,
                                     const std::shared_ptr<SearchState>& state) {
  pagmo::problem problem{GridProblem{state}};
  if (problem.get_nc() > 0) problem = pagmo::problem{pagmo::unconstrain{problem, "death penalty"}};
  const pagmo::bfe batch{PrefetchBfe{state}};
  const auto seed = static_cast<unsigned>(spec.seed);
  // Crossover 0.95 and distribution indices 10 / 50 are pagmo's defaults; the mutation rate is
  // one gene per design on average (1 / genes), the usual choice for integer chromosomes.
  pagmo::nsga2 algorithm(1u, 0.95, 10., 1.0 / double(state->genes.size()), 50., seed);
  algorithm.set_bfe(batch);
  pagmo::population population(problem, batch, spec.population, seed);
  std::vector<std::size_t> evaluated_after{state->order.size()};
  for (std::size_t g = 1; g <= spec.generations; ++g) {
    population = algorithm.evolve(population);
    evaluated_after.push_back(state->order.size());
  }
  // The reference point: 1 % beyond the worst feasible value of each objective over the whole
  // search (or 1 beyond it when that value is 0), so that every generation is measured alike.
  std::vector<double> reference(spec.objectives.size(), -std::numeric_limits<double>::infinity());
  for (std::size_t k = 0; k < state->order.size(); ++k) {
    if (!state->feasible[k]) continue;
    for (std::size_t i = 0; i < reference.size(); ++i) {
      reference[i] = std::max(reference[i], state->minimized[k][i]);
    }
  }
  for (double& r : reference) r = std::isfinite(r) ? r + std::max(1.0, std::abs(r)) * 0.01 : 0;
  std::vector<SearchGeneration> table;
  for (std::size_t g = 0; g < evaluated_after.size(); ++g) {
    std::vector<std::vector<double>> rows;
    for (std::size_t k = 0; k < evaluated_after[g]; ++k) {
      if (state->feasible[k]) rows.push_back(state->minimized[k]);
    }
    std::vector<bool> minimize(spec.objectives.size(), false);
    SearchGeneration row;
    row.generation = g;
    row.evaluations = evaluated_after[g];
    row.front_size = pareto_front(rows, minimize).size();
    row.hypervolume = front_hypervolume(rows, reference);
    table.push_back(row);
  }
  return table;
}

}  // namespace

}  // namespace edx::arch
