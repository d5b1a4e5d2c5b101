// maille-viewer SCENE: watch, drag and tune a scene live. See README.md ("The viewer").
#include <CLI/CLI.hpp>
#include <iostream>
#include <string>
#include <vector>

#include "maille/cores.hpp"
#include "maille/gpu.hpp"
#include "viewer.hpp"

int main(int argc, char** argv) {
  // The viewer's render loop holds a core: its physics threads wait passively (cores.hpp).
  maille::wait_passively_when_cores_are_shared(argv, true);
  maille::gpu::register_backend();
  maille::viewer::ViewerOptions o;
  CLI::App app{"Maille viewer: run a scene live, drag particles, tune parameters"};
  std::string scene, examples = MAILLE_EXAMPLES_DIR, screenshot;
  std::vector<std::string> stage_options;
  app.add_option("scene", scene, "Scene file (TOML)")->required()->check(CLI::ExistingFile);
  app.add_option("--examples", examples, "Directory listed by the scene picker");
  app.add_option("--width", o.width, "Window width")->check(CLI::Range(1, 16384));
  app.add_option("--height", o.height, "Window height")->check(CLI::Range(1, 16384));
  app.add_option("--frames", o.frames, "Draw this many frames, then exit (tests)")
      ->check(CLI::Range(1, 1000000000));
  app.add_option("--screenshot", screenshot, "With --frames: write the last frame here (PNG)");
  app.add_flag("--paused", o.paused, "Start paused");
  app.add_option("--backend", o.backend,
                 "Where the step runs: cpu or gpu (OpenGL 4.5 compute); default: the scene's");
  app.add_flag("--smooth", o.smooth, "Draw cloth as a smooth surface through the particles");
  app.add_option("--lod", o.lod, "Smooth surface: sub-segments per physical edge")
      ->check(CLI::Range(1, 16));
  app.add_flag("--sound", o.sound,
               "Sound on from the start: the scene's [[listen]] channels (the Sound panel)");
  app.add_option("--sound-driver", o.sound_driver, "With --sound: jack, pulse or alsa")
      ->check(CLI::IsMember({"jack", "pulse", "alsa"}));
  app.add_option("--sound-device", o.sound_device,
                 "With --sound: a JACK port prefix, or part of a device's name");
  app.add_option("--stage-option", stage_options,
                 "STAGE.OPTION=VALUE, repeatable: set as from the Stages panel, e.g. "
                 "obstacle:ball.method=facets");
  CLI11_PARSE(app, argc, argv);
  for (const auto& text : stage_options) {
    const auto dot = text.find('.'), eq = text.find('=');
    if (dot == std::string::npos || eq == std::string::npos || eq < dot) {
      std::cerr << "--stage-option: expected STAGE.OPTION=VALUE, got '" << text << "'\n";
      return 2;
    }
    o.stage_options.push_back(
        {text.substr(0, dot), text.substr(dot + 1, eq - dot - 1), text.substr(eq + 1)});
  }
  o.scene = scene;
  o.examples = examples;
  o.screenshot = screenshot;
  return maille::viewer::run_viewer(o);
}
