#include "arch/cost/resources.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace edx::arch::cost {

Resources& Resources::operator+=(const Resources& o) {
  lut += o.lut, ff += o.ff, dsp += o.dsp, bram += o.bram;
  return *this;
}

double Resources::operator[](int index) const {
  switch (index) {
    case 0:
      return lut;
    case 1:
      return ff;
    case 2:
      return dsp;
    case 3:
      return bram;
  }
  throw std::out_of_range(fmt::format("Resources: index {} is not 0..3", index));
}

nlohmann::json Resources::to_json() const {
  return {{"lut", lut}, {"ff", ff}, {"dsp", dsp}, {"bram_blocks", bram}};
}

CostEntry CostEntry::replicated(std::string name, std::string group, std::string kind,
                                const Resources& shared, double ns_copies) {
  return {std::move(name), std::move(group), std::move(kind),
          shared,          ns_copies,        shared * ns_copies};
}

nlohmann::json CostEntry::to_json() const {
  return {{"name", name},           {"group", group},
          {"kind", kind},           {"shared", shared.to_json()},
          {"ns_copies", ns_copies}, {"ns", ns.to_json()}};
}

Arithmetic parse_arithmetic(const std::string& text, const std::string& what) {
  if (text == "fixed") return Arithmetic::kFixed;
  if (text == "single") return Arithmetic::kSingle;
  if (text == "double") return Arithmetic::kDouble;
  throw std::runtime_error(
      fmt::format("{}: expected fixed, single or double, got '{}'", what, text));
}

const char* to_string(Arithmetic arithmetic) {
  switch (arithmetic) {
    case Arithmetic::kFixed:
      return "fixed";
    case Arithmetic::kSingle:
      return "single";
    case Arithmetic::kDouble:
      return "double";
  }
  return "?";
}

Datapath& Datapath::adders(double count, int bits) {
  r_.lut += count * bits;
  r_.ff += count * bits;
  return *this;
}

Datapath& Datapath::comparators(double count, int bits) {
  r_.lut += count * bits;
  r_.ff += count;
  return *this;
}

Datapath& Datapath::abs_diffs(double count, int bits) {
  r_.lut += count * 2 * bits;
  r_.ff += count * bits;
  return *this;
}

Datapath& Datapath::reductions(double count, int inputs) {
  r_.lut += count * std::ceil((inputs - 1) / 5.0);
  r_.ff += count;
  return *this;
}

Datapath& Datapath::xors(double count, int bits) {
  r_.lut += count * std::ceil(bits / 2.0);
  return *this;
}

Datapath& Datapath::muxes(double count, std::int64_t bits, std::int64_t ways) {
  r_.lut += count * double(bits) * std::ceil(double(ways - 1) / 3.0);
  return *this;
}

int Datapath::adder_tree(double count, int inputs, int bits) {
  int width = bits;
  for (int m = inputs; m > 1; m = (m + 1) / 2) {
    ++width;
    adders(count * (m / 2), width);
  }
  return width;
}

Datapath& Datapath::popcounts(double count, int bits) {
  adder_tree(count, bits, 0);
  return *this;
}

Datapath& Datapath::multipliers(double count, int a_bits, int b_bits) {
  r_.dsp += count * std::ceil(a_bits / 25.0) * std::ceil(b_bits / 18.0);
  return *this;
}

Datapath& Datapath::registers(double bits) {
  r_.ff += bits;
  return *this;
}

Datapath& Datapath::fp(double count, const FpOperatorCost& op) {
  r_ += op.resources() * count;
  return *this;
}

Datapath& Datapath::macs(double count, Arithmetic arithmetic, int a_bits, int b_bits) {
  switch (arithmetic) {
    case Arithmetic::kFixed:
      return multipliers(count, a_bits, b_bits);
    case Arithmetic::kSingle:
      return fp(count, kSingleMultiply).fp(count, kSingleAdd);
    case Arithmetic::kDouble:
      return fp(count, kDoubleMultiply).fp(count, kDoubleAdd);
  }
  return *this;
}

Datapath& Datapath::divider(double count, Arithmetic arithmetic) {
  if (arithmetic == Arithmetic::kDouble) return fp(count, kDoubleDivide);
  if (arithmetic == Arithmetic::kSingle) return fp(count, kSingleDivide);
  // Fixed point: a radix-2 restoring divider of 32 bits, one subtract-compare stage a bit.
  return adders(count * 32, 32);
}

Datapath& Datapath::sqrt(double count, Arithmetic arithmetic) {
  if (arithmetic == Arithmetic::kDouble) return fp(count, kDoubleSqrt);
  if (arithmetic == Arithmetic::kSingle) return fp(count, kSingleSqrt);
  return adders(count * 16, 32);  // digit-recurrence square root of 32 bits
}

Datapath& Datapath::bram(double blocks) {
  r_.bram += blocks;
  return *this;
}

int word_bits(Arithmetic arithmetic) { return arithmetic == Arithmetic::kSingle ? 32 : 64; }

void address_generator(Datapath& datapath) { datapath.adders(3, 16); }

}  // namespace edx::arch::cost
