// Temporary names for files written whole and renamed (stacks, manifests, preview folders), and
// the clean-up of those that a killed process left behind. A temporary is NAME.tmp-HOST-PID: the
// host makes the PID meaningful on a file system shared by a cluster's machines, and a leftover is
// judged stale only when it is this host's and no process PID lives here. Leftovers of other
// hosts, and the older host-less NAME.tmp-PID, are never removed (no one here can tell).
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace skypol::stack {

// This machine's name as it appears in temporary names: gethostname(), with anything but
// letters, digits, '.', '_' and '-' replaced by '_' ("localhost" if it has none).
std::string host_name();

// `path` + ".tmp-HOST-PID" for this process.
std::string temp_name(const std::string& path);

// Every stale temporary in `dir`, keyed by the NAME it was to become (a file name in `dir`).
std::map<std::string, std::vector<std::filesystem::path>> stale_temporaries(const std::filesystem::path& dir);

// Removes the stale temporaries of `path` (files or folders); errors are ignored (someone else's
// clean-up may have been faster).
void remove_stale_temporaries(const std::string& path);

}  // namespace skypol::stack
