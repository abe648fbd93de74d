// softpbr — the command line: render scene files, compare images, inspect models.
//
//   softpbr render SCENE.json -o OUT.png [--width W --height H --threads N --tile-size T
//                  --tonemap NAME --exposure E --frames A..B --shard i/N]
//   softpbr diff A.png B.png [--max-diff N --max-pixels P --out diff.png]
//   softpbr diff A.glb B.glb [--views N | --yaw LIST --pitch LIST] [--out sheet.png --json F]
//   softpbr thumbnail -s SIZE IN.glb OUT.png [--timeout S --max-memory MIB]
//   softpbr info MODEL.obj | MODEL.gltf | MODEL.glb | SCENE.json
//   softpbr version | --version
//
// Every failure is one line on stderr and an exit code (cli_error.h).
#include <cstdio>
#include <exception>
#include <new>
#include <string>

#include <CLI/CLI.hpp>

#include "cli_error.h"
#include "diff.h"
#include "info.h"
#include "render.h"
#include "thumbnail.h"
#include "version.h"

namespace {
// Every error is one bounded line (cli_error.h's printable_line).
void print_error(const std::string& what) { std::fprintf(stderr, "%s\n", softpbr::cli::printable_line(what).c_str()); }
}  // namespace

int main(int argc, char** argv) {
  using namespace softpbr::cli;
  CLI::App app{"softpbr: bit-exact physically based rendering on the CPU"};
  app.require_subcommand(1);
  app.footer(std::string(kExitCodesHelp) + "\nScene files: docs/scene-format.md");
  RenderArgs render;
  InfoArgs info;
  DiffArgs diff;
  ThumbnailArgs thumbnail;
  CLI::App* render_cmd = add_render_command(app, render);
  CLI::App* info_cmd = add_info_command(app, info);
  CLI::App* diff_cmd = add_diff_command(app, diff);
  CLI::App* thumbnail_cmd = add_thumbnail_command(app, thumbnail);
  CLI::App* version_cmd = add_version_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    // CLI11's own output is two lines ("…\nRun with --help for more information."): one here.
    print_error(std::string("softpbr: ") + e.what() + " (see --help)");
    return kExitUsage;
  }
  const bool diffing = diff_cmd->parsed();
  try {
    if (render_cmd->parsed()) return run_render(render);
    if (info_cmd->parsed()) return run_info(info);
    if (version_cmd->parsed()) return run_version();
    if (thumbnail_cmd->parsed()) return run_thumbnail(thumbnail);
    return run_diff(diff);
  } catch (const Error& e) {
    print_error(e.what());
    return diffing && e.code() != kExitDifferent ? kExitUsage : e.code();
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "softpbr: out of memory\n");
    return diffing ? kExitUsage : kExitInput;
  } catch (const std::exception& e) {
    print_error(std::string("softpbr: internal error: ") + e.what());
    return diffing ? kExitUsage : kExitInternal;
  }
}
