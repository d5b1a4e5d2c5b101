// maille-viewer SCENE: watch, drag and tune a scene live. See README.md ("The viewer").
#include <CLI/CLI.hpp>

#include "viewer.hpp"

int main(int argc, char** argv) {
  maille::viewer::ViewerOptions o;
  CLI::App app{"Maille viewer: run a scene live, drag particles, tune parameters"};
  std::string scene, examples = MAILLE_EXAMPLES_DIR, screenshot;
  app.add_option("scene", scene, "Scene file (TOML)")->required()->check(CLI::ExistingFile);
  app.add_option("--examples", examples, "Directory listed by the scene picker");
  app.add_option("--width", o.width, "Window width")->check(CLI::PositiveNumber);
  app.add_option("--height", o.height, "Window height")->check(CLI::PositiveNumber);
  app.add_option("--frames", o.frames, "Draw this many frames, then exit (tests)")
      ->check(CLI::PositiveNumber);
  app.add_option("--screenshot", screenshot, "With --frames: write the last frame here (PNG)");
  app.add_flag("--paused", o.paused, "Start paused");
  CLI11_PARSE(app, argc, argv);
  o.scene = scene;
  o.examples = examples;
  o.screenshot = screenshot;
  return maille::viewer::run_viewer(o);
}
