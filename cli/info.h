// info.h — `softpbr info FILE`: what an OBJ or glTF model or a scene file holds and the problems
// found in it.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace softpbr::cli {

struct InfoArgs {
  std::string file;
};

CLI::App* add_info_command(CLI::App& app, InfoArgs& args);
int run_info(const InfoArgs& args);

}  // namespace softpbr::cli
