#pragma once
// aar-render's flags shared by render, calib and bench: the options of a
// render job as the command line gives them, and their resolution into
// RenderJobOptions (the sun, daylight, night, floodlight, auto-exposure).

#include <optional>
#include <string>
#include <vector>

#include "aar/renderer/background.h"
#include "aar/renderer/stereo_render_job.h"

namespace CLI {
class App;
}

namespace aar {

/// "30,45" for {30, 45}; "none" for no far boards.
std::string FarBoardsText(const std::vector<double>& distances_m);
/// Parses --far-boards: comma-separated distances [m], or "none".
std::vector<double> ParseFarBoards(const std::string& text);

/// Flags shared by render, calib and bench; the defaults are RenderJobOptions'.
struct JobFlags {
  aar::RenderJobOptions job;
  std::string frames;
  std::string shard;
  std::string background = aar::BackgroundName(aar::BackgroundOptions{}.kind);
  std::string far_boards = FarBoardsText(aar::RenderJobOptions{}.far_boards_m);
  std::optional<double> sun_azimuth_deg, sun_elevation_deg, latitude_deg, longitude_deg, heading_deg;
  std::string sun_time;
  bool daylight = false;
  std::optional<double> turbidity;
  bool night = false;
  std::optional<double> moonlight_lx;
  std::optional<double> floodlight_lx, floodlight_beam_deg;
  bool auto_exposure = false;
  std::optional<double> ae_target, ae_time_constant_s, ae_max_ev;
  std::optional<double> airspeed_mps, sky_temperature_k, nacelle_excess_k, board_temperature_k;
  std::string shading = aar::ToString(aar::RenderJobOptions{}.shading);
};

/// Adds the job's flags to `cmd` (calib: the board's; otherwise the flight path's, its scene and light).
void AddJobFlags(CLI::App& cmd, JobFlags& f, bool calib);
/// Of a flight-path job: the sun, daylight, night, floodlight and auto-exposure
/// the flags give into f.job, each refused where its flags disagree.
void ResolveLightingFlags(JobFlags& f);
/// Of a calibration job: the far boards and a thermal rig's board temperature into f.job.
void ResolveCalibFlags(JobFlags& f);

}  // namespace aar
