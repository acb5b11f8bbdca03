// Runs the real polder program through the shell and keeps what a user would see.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace polder::test {

struct ProgramRun {
  int exitCode = -1;
  std::string output;  // stdout and stderr together
};

// `prefix` runs in the same shell before the program (a `ulimit`, say).
inline ProgramRun runPolder(const std::string& arguments, const std::string& prefix = "") {
  const std::string command = prefix + std::string(POLDER_EXECUTABLE) + " " + arguments + " 2>&1";
  ProgramRun run;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return run;
  std::array<char, 4096> buffer;
  std::size_t read = 0;
  while ((read = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) run.output.append(buffer.data(), read);
  const int status = ::pclose(pipe);
  run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return run;
}

}  // namespace polder::test
