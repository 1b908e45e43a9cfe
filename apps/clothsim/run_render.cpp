// The --render family of flags of `clothsim run` (run_render.h).
#include "run_render.h"

#include <string>

namespace clothsim::cli {

void add_render_flags(CLI::App& app, RenderFlags& flags) {
  const RenderFlags defaults;
  flags = defaults;
  app.add_option("--render", flags.render,
                 "pictures to write: all (final.png and animation.mp4), image, video or none (no OpenGL at all, "
                 "for batch runs)")
      ->type_name("WHAT")
      ->default_str(defaults.render)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app.add_option("--size", flags.size,
                 "image and video size in pixels, each side in [" + std::to_string(kMinPictureSide) + ", " +
                     std::to_string(kMaxPictureSide) + "]")
      ->type_name("WxH")
      ->default_str(defaults.size)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app.add_option("--camera", flags.camera,
                 "auto (frame everything seen so far), follow (glide after the sheet), or AZIMUTH,ELEVATION[,DISTANCE] "
                 "in degrees and metres (auto framing from that direction; a distance fixes the camera)")
      ->type_name("MODE")
      ->default_str(defaults.camera)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app.add_option("--mesh", flags.mesh,
                 "rendered mesh: particles (vertices at the masses) or cell-centres (the paper's: vertices at the "
                 "centres of 4 masses)")
      ->type_name("MODE")
      ->default_str(defaults.mesh)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app.add_option("--samples", flags.samples,
                 "anti-aliasing samples per pixel (MSAA), an integer in [1, 16]; 1 turns it off (about 3x faster on "
                 "a software renderer)")
      ->type_name("N")
      ->default_str(defaults.samples)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app.add_option("--show", flags.show,
                 "overlays, comma-separated: connectors, radials, wireframe; and no-ground, no-anchors")
      ->type_name("LIST")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
}

}  // namespace clothsim::cli
