# The monitor's page (src/hybridtest/monitor/web/) embedded in hybridtest_monitor, with uPlot
# from npm when it can be had: at configure time, `npm install uplot@VERSION` into the build
# directory (never committed, never fetched when the page is viewed). Without npm or a
# network the build goes on and the page draws on a plain canvas (it says so).
option(HYBRIDTEST_FETCH_UPLOT "Fetch uPlot from npm into the build tree for the monitor's page" ON)
set(HYBRIDTEST_UPLOT_VERSION 1.6.32)
set(uplot_prefix ${PROJECT_BINARY_DIR}/npm)
set(uplot_dist ${uplot_prefix}/node_modules/uplot/dist)
if(HYBRIDTEST_FETCH_UPLOT AND NOT EXISTS ${uplot_dist}/uPlot.iife.min.js)
  find_program(HYBRIDTEST_NPM npm)
  if(HYBRIDTEST_NPM)
    message(STATUS "monitor: fetching uPlot ${HYBRIDTEST_UPLOT_VERSION} with npm into ${uplot_prefix}")
    file(MAKE_DIRECTORY ${uplot_prefix})
    execute_process(COMMAND ${HYBRIDTEST_NPM} install --prefix ${uplot_prefix} --no-save --no-audit
                            --no-fund --ignore-scripts uplot@${HYBRIDTEST_UPLOT_VERSION}
                    RESULT_VARIABLE npm_result OUTPUT_QUIET ERROR_QUIET TIMEOUT 180)
  endif()
endif()
if(EXISTS ${uplot_dist}/uPlot.iife.min.js)
  message(STATUS "monitor: uPlot bundled from ${uplot_dist}")
else()
  message(STATUS "monitor: uPlot not available (no npm or no network): the page uses plain canvas plots")
endif()

set(monitor_web_dir ${CMAKE_CURRENT_SOURCE_DIR}/monitor/web)
set(monitor_page_cc ${CMAKE_CURRENT_BINARY_DIR}/generated/monitor_page_assets.cc)
add_custom_command(
  OUTPUT ${monitor_page_cc}
  COMMAND ${CMAKE_COMMAND} -DWEB_DIR=${monitor_web_dir} -DOUT=${monitor_page_cc}
          -DUPLOT_JS=${uplot_dist}/uPlot.iife.min.js -DUPLOT_CSS=${uplot_dist}/uPlot.min.css
          -P ${PROJECT_SOURCE_DIR}/cmake/EmbedMonitorPage.cmake
  DEPENDS ${monitor_web_dir}/index.html ${monitor_web_dir}/monitor.js ${monitor_web_dir}/monitor.css
          ${PROJECT_SOURCE_DIR}/cmake/EmbedMonitorPage.cmake
  COMMENT "Embedding the monitor's page")
target_sources(hybridtest_monitor PRIVATE ${monitor_page_cc})
