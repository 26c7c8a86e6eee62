#include "stack/temp_files.h"

#include <cerrno>
#include <csignal>
#include <system_error>

#include <sys/types.h>
#include <unistd.h>

namespace skypol::stack {
namespace fs = std::filesystem;

std::string host_name() {
  char buf[256] = {};
  if (::gethostname(buf, sizeof buf - 1) != 0) buf[0] = '\0';
  std::string out;
  for (const char* c = buf; *c; ++c) {
    const bool ok = (*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9') || *c == '.' ||
                    *c == '_' || *c == '-';
    out += ok ? *c : '_';
  }
  return out.empty() ? "localhost" : out;
}

std::string temp_name(const std::string& path) {
  return path + ".tmp-" + host_name() + "-" + std::to_string(::getpid());
}

std::map<std::string, std::vector<fs::path>> stale_temporaries(const fs::path& dir) {
  std::map<std::string, std::vector<fs::path>> out;
  const std::string mark = ".tmp-" + host_name() + "-";
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const auto at = name.rfind(mark);
    if (at == std::string::npos || at == 0) continue;
    const std::string pid = name.substr(at + mark.size());
    if (pid.empty() || pid.size() > 9 || pid.find_first_not_of("0123456789") != std::string::npos) continue;
    if (::kill(static_cast<pid_t>(std::stol(pid)), 0) == 0 || errno != ESRCH) continue;  // alive, or not ours to judge
    out[name.substr(0, at)].push_back(it->path());
  }
  return out;
}

void remove_stale_temporaries(const std::string& path) {
  const fs::path p(path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::map<std::string, std::vector<fs::path>> stale = stale_temporaries(dir);
  const auto it = stale.find(p.filename().string());
  if (it == stale.end()) return;
  std::error_code ec;
  for (const fs::path& leftover : it->second) fs::remove_all(leftover, ec);
}

}  // namespace skypol::stack
