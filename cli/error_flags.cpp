#include "error_flags.h"

#include "megavox/error.h"

namespace mv::cli {

namespace {

struct SettingFlag {
  Setting setting;
  const char* flag;
};

const SettingFlag kSettingFlags[] = {
    {setting_resolution, "--resolution"},     {setting_cube, "--cube"},
    {setting_encoding, "--format"},           {setting_voxelize, "--voxelize"},
    {setting_grid_origin, "--grid-origin"},   {setting_bounds, "--bounds"},
    {setting_host_memory, "--memory"},        {setting_device_memory, "--device-memory"},
    {setting_lod_pixels, "--lod-pixels"},     {setting_ao_radius, "--ao-radius"},
    {setting_cache_memory, "--cache-memory"}, {setting_width, "--width"},
    {setting_depth, "--depth"},               {setting_max_node_points, "--max-node-points"},
    {setting_no_clobber, "--no-clobber"},     {setting_frames, "--frames"},
    {setting_eye, "--eye"},                   {setting_target, "--target"},
    {setting_up, "--up"},                     {setting_fov, "--fov"},
    {setting_view, "--view"},
};

}  // namespace

std::string message_with_flags(const std::exception& e) {
  const std::string message = error_message(e);
  const Setting settings = error_settings(e);
  std::string flags;
  for (const SettingFlag& f : kSettingFlags)
    if (settings & f.setting) flags += (flags.empty() ? "" : ", ") + std::string(f.flag);
  if (flags.empty()) return message;
  // A budget that ran out is the one setting whose remedy is always the same.
  const bool budget = settings == setting_device_memory || settings == setting_host_memory;
  const bool raise = budget && classify(e) == ErrorCode::out_of_memory;
  return message + " (" + (raise ? "raise " : "") + flags + ")";
}

}  // namespace mv::cli
