// Shared helpers for colosim's tests: paths of the shipped assets and of temporary files.
#pragma once

#include <cstdio>
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

inline std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace colosim::test
