#pragma once
// The monitor's page, embedded in the binary at build time: web/index.html, web/monitor.js,
// web/monitor.css, and uPlot's script and style when the build fetched them from npm
// (cmake/MonitorAssets.cmake). Nothing is loaded from the network when the page is viewed.
#include <span>
#include <string_view>

namespace hybridtest::monitor {

struct PageAsset {
  std::string_view path;          // "/", "/monitor.js", "/uplot.js", ...
  std::string_view content_type;  // "text/html; charset=utf-8", ...
  std::string_view body;
};

std::span<const PageAsset> PageAssets();
// Whether uPlot was bundled (else the page draws on a plain canvas and says so).
bool HasUplot();

}  // namespace hybridtest::monitor
