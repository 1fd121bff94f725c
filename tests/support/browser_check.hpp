#pragma once
// The report page's self-check in headless Chromium (docs/REPORTS.md, index.html?browser-check):
// the JSON the page appends after load, {images, broken, wide, viewport, scroll_width}.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "tests/support/run_command.hpp"

namespace edx::testing {

/// Whether headless Chromium is here (./edx test installs it).
inline bool chromium_available() { return run_command("command -v chromium").exit_code == 0; }

/// Opens `index_html` at 1280 px in headless Chromium (profile in `profile_dir`) and returns the
/// page's check; a failed assertion (and nullopt) when the page did not load or its check did
/// not run.
inline std::optional<nlohmann::json> browser_check(const std::filesystem::path& index_html,
                                                   const std::filesystem::path& profile_dir) {
  const auto dom = run_command(
      "chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --window-size=1280,2000 "
      "--virtual-time-budget=10000 --user-data-dir=" +
      profile_dir.string() + " --dump-dom 'file://" + index_html.string() +
      "?browser-check' 2>/dev/null");
  EXPECT_EQ(dom.exit_code, 0);
  const std::string open_tag = "<pre id=\"browser-check\">";
  const std::size_t begin = dom.out.find(open_tag);
  EXPECT_NE(begin, std::string::npos) << "the page did not load or its check did not run";
  if (dom.exit_code != 0 || begin == std::string::npos) return std::nullopt;
  const std::size_t end = dom.out.find("</pre>", begin);
  return nlohmann::json::parse(
      dom.out.substr(begin + open_tag.size(), end - begin - open_tag.size()));
}

}  // namespace edx::testing
