#include "sim_core/stats.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>

namespace edx::sim {

TimeWeighted::TimeWeighted(const Simulator& sim, double initial)
    : sim_(&sim), current_(initial), max_(initial), start_(sim.now()), last_change_(sim.now()) {}

void TimeWeighted::set(double value) {
  const Time now = sim_->now();
  // Close the constant piece [last_change_, now) at the old value.
  area_ += current_ * static_cast<double>(now - last_change_);
  last_change_ = now;
  current_ = value;
  max_ = std::max(max_, value);
}

void TimeWeighted::set_at(Time when, double value) {
  if (when < last_change_ || when > sim_->now()) {
    throw std::logic_error("edx::sim::TimeWeighted::set_at(" + std::to_string(when) +
                           " ps): expected a time between the last change (" +
                           std::to_string(last_change_) + " ps) and now (" +
                           std::to_string(sim_->now()) + " ps)");
  }
  area_ += current_ * static_cast<double>(when - last_change_);
  last_change_ = when;
  current_ = value;
  max_ = std::max(max_, value);
}

void TimeWeighted::reset() {
  start_ = last_change_ = sim_->now();
  area_ = 0.0;
  max_ = current_;
}

double TimeWeighted::integral() const {
  return area_ + current_ * static_cast<double>(sim_->now() - last_change_);
}

Time TimeWeighted::elapsed() const { return sim_->now() - start_; }

double TimeWeighted::mean() const {
  const Time window = elapsed();
  if (window == 0) {
    throw std::domain_error("edx::sim::TimeWeighted::mean: the averaging window is empty");
  }
  return integral() / static_cast<double>(window);
}

// ------------------------------------------------------------------------------ StatsRegistry

namespace {

std::vector<std::string> split_name(const std::string& name) {
  std::vector<std::string> segments;
  std::size_t begin = 0;
  for (;;) {
    const std::size_t dot = name.find('.', begin);
    segments.push_back(
        name.substr(begin, dot == std::string::npos ? std::string::npos : dot - begin));
    if (dot == std::string::npos) break;
    begin = dot + 1;
  }
  return segments;
}

/// Value of an optional statistic: calls `statistic` and maps std::domain_error to null.
template <class Function>
nlohmann::json defined_or_null(Function statistic) {
  try {
    return statistic();
  } catch (const std::domain_error&) {
    return nullptr;
  }
}

nlohmann::json describe(const SampleSet& s) {
  return {{"count", s.count()},
          {"mean", defined_or_null([&] { return s.mean(); })},
          {"sd", defined_or_null([&] { return s.sd(); })},
          {"rsd", defined_or_null([&] { return s.rsd(); })},
          {"min", defined_or_null([&] { return s.min(); })},
          {"p50", defined_or_null([&] { return s.p50(); })},
          {"p90", defined_or_null([&] { return s.p90(); })},
          {"p99", defined_or_null([&] { return s.p99(); })},
          {"max", defined_or_null([&] { return s.max(); })}};
}

nlohmann::json describe(const TimeWeighted& t) {
  return {{"mean", defined_or_null([&] { return t.mean(); })},
          {"max", t.max()},
          {"current", t.current()},
          {"elapsed_ps", t.elapsed()}};
}

std::string format_number(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

}  // namespace

void StatsRegistry::insert(const std::string& name, Entry entry) {
  const auto fail = [&](const std::string& why) {
    throw std::invalid_argument("edx::sim::StatsRegistry: statistic '" + name + "' " + why);
  };
  for (const std::string& segment : split_name(name)) {
    if (segment.empty()) fail("has an empty name segment");
    for (char c : segment) {
      if (c == ' ' || c == '\t' || c == '\n' || c == '\r') fail("contains whitespace");
    }
  }
  if (entries_.count(name) != 0) fail("is already registered");
  // A name may not be both a leaf and a group: no registered name may be a segment prefix of
  // this one, and this one may not be a segment prefix of a registered name.
  for (std::size_t dot = name.find('.'); dot != std::string::npos; dot = name.find('.', dot + 1)) {
    if (entries_.count(name.substr(0, dot)) != 0) {
      fail("lies below the registered statistic '" + name.substr(0, dot) + "'");
    }
  }
  const std::string group = name + ".";
  const auto below = entries_.lower_bound(group);
  if (below != entries_.end() && below->first.compare(0, group.size(), group) == 0) {
    fail("is a group of the registered statistic '" + below->first + "'");
  }
  entries_.emplace(name, std::move(entry));
}

void StatsRegistry::add(const std::string& name, const Counter& counter) { insert(name, &counter); }

void StatsRegistry::add(const std::string& name, const SampleSet& samples) {
  insert(name, &samples);
}

void StatsRegistry::add(const std::string& name, const TimeWeighted& quantity) {
  insert(name, &quantity);
}

void StatsRegistry::add_gauge(const std::string& name, std::function<double()> gauge) {
  if (!gauge) {
    throw std::invalid_argument("edx::sim::StatsRegistry: gauge '" + name + "' is empty");
  }
  insert(name, std::move(gauge));
}

nlohmann::json StatsRegistry::to_json() const {
  nlohmann::json root = nlohmann::json::object();
  for (const auto& [name, entry] : entries_) {
    nlohmann::json* node = &root;
    for (const std::string& segment : split_name(name)) node = &(*node)[segment];
    if (const auto* counter = std::get_if<const Counter*>(&entry)) {
      *node = (*counter)->value();
    } else if (const auto* samples = std::get_if<const SampleSet*>(&entry)) {
      *node = describe(**samples);
    } else if (const auto* quantity = std::get_if<const TimeWeighted*>(&entry)) {
      *node = describe(**quantity);
    } else {
      *node = defined_or_null(std::get<std::function<double()>>(entry));
    }
  }
  return root;
}

std::vector<std::pair<std::string, double>> StatsRegistry::to_listing() const {
  std::vector<std::pair<std::string, double>> listing;
  const auto emit_fields = [&](const std::string& name, const nlohmann::json& fields) {
    for (const auto& [field, value] : fields.items()) {
      if (!value.is_null()) listing.emplace_back(name + "." + field, value.get<double>());
    }
  };
  for (const auto& [name, entry] : entries_) {
    if (const auto* counter = std::get_if<const Counter*>(&entry)) {
      listing.emplace_back(name, static_cast<double>((*counter)->value()));
    } else if (const auto* samples = std::get_if<const SampleSet*>(&entry)) {
      emit_fields(name, describe(**samples));
    } else if (const auto* quantity = std::get_if<const TimeWeighted*>(&entry)) {
      emit_fields(name, describe(**quantity));
    } else {
      const nlohmann::json value = defined_or_null(std::get<std::function<double()>>(entry));
      if (!value.is_null()) listing.emplace_back(name, value.get<double>());
    }
  }
  std::sort(listing.begin(), listing.end());
  return listing;
}

std::string StatsRegistry::to_text() const {
  std::string text;
  for (const auto& [name, value] : to_listing()) {
    text += name;
    text += ' ';
    text += format_number(value);
    text += '\n';
  }
  return text;
}

}  // namespace edx::sim
