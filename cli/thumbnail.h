// thumbnail.h — `softpbr thumbnail -s SIZE IN OUT`: a desktop thumbnailer (the freedesktop.org
// thumbnail specification's command, run by file managers through
// share/thumbnailers/softpbr.thumbnailer on every model a user has): a SIZE×SIZE PNG with a
// transparent background, the model framed as `softpbr render model.glb` frames it. Built
// for hostile files: bounded time (--timeout), bounded memory (--max-memory, also the
// process's data limit), never a wait on a pipe or device, the output written whole or not
// at all.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace softpbr::cli {

struct ThumbnailArgs {
  std::string input, output;
  long size = 256;            // the specification's "large"; 128 normal, 512 x-large, 1024 xx-large
  double timeout = 10;        // seconds, 0: none
  double max_memory_mib = 1024;
  long threads = 0;
};

CLI::App* add_thumbnail_command(CLI::App& app, ThumbnailArgs& args);
int run_thumbnail(const ThumbnailArgs& args);

}  // namespace softpbr::cli
