// sarloc-report: a recording (sarloc-record, sarloc-mission) to one self-contained HTML report
// with maps, a timeline and tables (docs/operations/recording.md).
//
// Exit codes: 0 report written from a whole recording; 1 report written, but the recording is
// damaged (the report says what could not be read); 2 bad command line; 3 a --basemap that is
// not a raster MBTiles file; 4 not an MCAP file,
// unreadable, or the report (or the GeoJSON: also when the recording has no WGS-84 origin)
// cannot be written.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <fstream>
#include <memory>
#include <string>

#include "mission_record.hpp"
#include "report_geojson.hpp"
#include "report_html.hpp"
#include "sarloc/app/command_line.hpp"
#include "sarloc/app/logging.hpp"
#include "sarloc/app/progress_bar.hpp"
#include "sarloc/app/run_main.hpp"

int main(int argc, char** argv) {
  using namespace sarloc;
  CLI::App cli{"sarloc-report: a mission recording (.mcap) to a self-contained HTML report"};
  std::string recording, output = "report.html", compare, geojson, basemap_path, log_level = "info";
  cli.add_option("recording", recording, "the .mcap file")->required();
  cli.add_option("-o,--output", output, "the HTML file to write")->capture_default_str();
  cli.add_option("--compare", compare, "another recording of the same inputs: the report shows how this one differs from it");
  cli.add_option("--geojson", geojson,
                 "also write the deposit, strips, tracks and victims as GeoJSON (RFC 7946, WGS-84) to this file");
  cli.add_option("--basemap", basemap_path,
                 "an offline raster MBTiles file (as dashboard.basemap): its tiles under the avalanche field's map, "
                 "embedded in the report");
  app::add_log_level_option(cli, log_level);
  cli.set_version_flag("--version", SARLOC_VERSION);
  if (auto code = app::parse_command_line(cli, argc, argv)) return *code;

  return app::run_main("sarloc-report", [&] {
    app::setup_logging(log_level, "report");
    auto load = [](const std::string& path) {
      std::unique_ptr<app::ProgressBar> bar;
      std::uint64_t shown = 0;
      return report::load_mission_record(path, [&](std::uint64_t done, std::uint64_t total) {
        // Progress in MB read: the bar wants counts.
        if (!bar) bar = std::make_unique<app::ProgressBar>("reading " + path, static_cast<std::size_t>(total / 1000000 + 1));
        const std::uint64_t mb = done / 1000000;
        if (mb > shown) {
          bar->tick(static_cast<std::size_t>(mb - shown));
          shown = mb;
        }
      });
    };
    // Opened first: a wrong file is refused before minutes of reading a recording.
    std::unique_ptr<const app::Basemap> basemap;
    if (!basemap_path.empty()) basemap = std::make_unique<const app::Basemap>(basemap_path, "--basemap");
    const report::MissionRecord record = load(recording);
    if (basemap && !record.incident_origin) {
      spdlog::warn("no basemap drawn: the recording holds no WGS-84 origin of the incident to place it by");
    }
    std::unique_ptr<report::MissionRecord> baseline;
    if (!compare.empty()) baseline = std::make_unique<report::MissionRecord>(load(compare));
    const std::string html = report::render_report(record, baseline.get(), basemap.get());
    std::ofstream out(output, std::ios::binary | std::ios::trunc);
    out << html;
    out.close();
    if (!out) throw recording::RecordingError("cannot write the report to '" + output + "'");
    spdlog::info("report of '{}' ({} victims, {} responders, {} events) written to '{}'", recording, record.victims.size(),
                 record.responders.size(), record.events.size(), output);
    if (!geojson.empty()) {
      const nlohmann::json collection = report::render_geojson(record);
      std::ofstream geo(geojson, std::ios::binary | std::ios::trunc);
      geo << collection.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) << '\n';
      geo.close();
      if (!geo) throw recording::RecordingError("cannot write the GeoJSON to '" + geojson + "'");
      spdlog::info("GeoJSON ({} features) written to '{}'", collection["features"].size(), geojson);
    }
    if (!record.read.damage.empty()) {
      spdlog::warn("the recording is damaged: {}; the report shows what could be read", record.read.damage);
      return app::ExitCode::kFailure;
    }
    return app::ExitCode::kOk;
  });
}
