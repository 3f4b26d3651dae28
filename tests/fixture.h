// Shared helpers for colosim's tests: paths of the shipped assets and of temporary files.
#pragma once

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace colosim::test {

inline std::string asset(const std::string& relative) {
  return std::string(COLOSIM_ASSET_DIR) + "/" + relative;
}

/// A fresh temporary directory for one test, removed at destruction.
class TempDir {
 public:
  TempDir() {
    std::string tmpl = (std::filesystem::temp_directory_path() / "colosim-test-XXXXXX").string();
    path_ = mkdtemp(tmpl.data());
  }
  ~TempDir() { std::error_code ec; std::filesystem::remove_all(path_, ec); }
  std::string file(const std::string& name) const { return (std::filesystem::path(path_) / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    const std::string p = file(name);
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

/// What a command printed on stdout and how it exited.
struct CommandResult {
  int code = -1;    ///< exit status (-1: did not exit normally)
  std::string out;  ///< stdout (and whatever the command line redirects into it)
};

/// Runs `command_line` through the shell (with its own redirections, e.g. "2>&1").
inline CommandResult runCommand(const std::string& command_line) {
  CommandResult r;
  FILE* p = popen(command_line.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  size_t got;
  while ((got = fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), got);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

inline std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// A command's exit code, stdout and stderr.
struct CommandOutput : CommandResult {
  std::string err;  ///< stderr
};

/// Runs a command line with its stderr captured through a file in `dir`.
inline CommandOutput runCommandWithStderr(const std::string& command_line, const TempDir& dir) {
  const std::string err_file = dir.file("stderr.txt");
  CommandOutput r;
  static_cast<CommandResult&>(r) = runCommand(command_line + " 2>" + err_file);
  r.err = readFile(err_file);
  return r;
}

#ifdef COLOSIM_EXE
/// Runs the colosim command (the target's COLOSIM_EXE) with `args`, stderr captured in `dir`.
inline CommandOutput runColosim(const std::string& args, const TempDir& dir) {
  return runCommandWithStderr(std::string(COLOSIM_EXE) + " " + args, dir);
}
#endif

}  // namespace colosim::test
