// Checks shared by every subcommand's options of one kind (commands.hpp).
#include <array>
#include <string>
#include <string_view>

#include "cli/commands.hpp"
#include "workloads/datasets/dataset.hpp"

namespace edx::cli {

void check_common_options(CLI::App& app) {
  static constexpr std::array<std::string_view, 14> kPathOptions{
      "out",     "db",  "trace", "config", "data", "results",  "timeline",
      "dataset", "map", "vocab", "gt",     "est",  "save-map", "datasets"};
  const CLI::Validator non_empty(
      [](std::string& value) {
        return value.empty() ? std::string("expected a path, got ''") : std::string();
      },
      "PATH");
  const CLI::Validator non_negative(
      [](std::string& value) {
        const bool digits = !value.empty() && value.find_first_not_of("0123456789") == value.npos;
        return digits ? std::string() : "expected a non-negative integer, got '" + value + "'";
      },
      "UINT");
  for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; })) {
    for (CLI::Option* option : command->get_options([](CLI::Option*) { return true; })) {
      for (const std::string& name : option->get_lnames()) {
        for (std::string_view path : kPathOptions) {
          if (name == path) option->check(non_empty);
        }
        if (name == "seed") option->check(non_negative);
      }
    }
  }
}

CLI::Validator resolution_validator() {
  return CLI::Validator(
      [](std::string& text) {
        try {
          datasets::parse_resolution(text);
        } catch (const std::exception& e) {
          return std::string(e.what());
        }
        return std::string();
      },
      "WxH");
}

}  // namespace edx::cli
