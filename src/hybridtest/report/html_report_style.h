#pragma once
// The report's inline stylesheet (no web fonts, no external files).
namespace hybridtest::report {

inline constexpr const char* kHtmlReportCss = R"css(
:root { --ink:#1d2430; --muted:#5b6577; --line:#dde2ea; --band:#f4f6f9; --accent:#1f4e8c; }
* { box-sizing: border-box; }
body { margin:0; font:15px/1.5 system-ui,-apple-system,"Segoe UI",Roboto,"Helvetica Neue",Arial,sans-serif;
       color:var(--ink); background:#eef1f5; }
main { max-width:1120px; margin:0 auto; padding:0 20px 48px; }
header.top { background:var(--accent); color:#fff; padding:28px 0 22px; margin-bottom:24px; }
header.top div { max-width:1120px; margin:0 auto; padding:0 20px; }
header.top h1 { margin:0 0 6px; font-size:26px; font-weight:600; }
header.top p { margin:0; opacity:.85; font-size:14px; }
section { background:#fff; border:1px solid var(--line); border-radius:8px; padding:18px 22px;
          margin:0 0 20px; }
h2 { font-size:18px; margin:0 0 12px; color:var(--accent); }
h3 { font-size:15px; margin:18px 0 8px; }
table { border-collapse:collapse; width:100%; font-size:14px; }
th, td { text-align:left; padding:6px 10px; border-bottom:1px solid var(--line); vertical-align:top; }
th { background:var(--band); font-weight:600; white-space:nowrap; }
td.num { text-align:right; font-variant-numeric:tabular-nums; white-space:nowrap; }
table.kv th { width:260px; }
pre { background:var(--band); border:1px solid var(--line); border-radius:6px; padding:12px;
      overflow:auto; font:13px/1.45 ui-monospace,"DejaVu Sans Mono",Menlo,Consolas,monospace; }
figure { margin:0 0 22px; }
figure img { width:100%; height:auto; border:1px solid var(--line); border-radius:6px; }
figcaption { color:var(--muted); font-size:13px; margin-top:4px; }
.badge { display:inline-block; padding:2px 10px; border-radius:12px; font-size:13px; font-weight:600; }
.ok { background:#e3f4e8; color:#1c6b35; } .bad { background:#fde6e6; color:#a11d1d; }
.busy { background:#fff3d6; color:#8a5a00; }
.note { color:var(--muted); font-size:13px; }
.physical { color:#c62828; font-weight:600; }
summary { cursor:pointer; font-weight:600; margin:6px 0; }
footer { color:var(--muted); font-size:12px; text-align:center; margin-top:10px; }
)css";

}  // namespace hybridtest::report
