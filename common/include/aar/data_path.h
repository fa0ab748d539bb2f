#pragma once
// Where the tools find their data (scenes/, flightpaths/, shaders/): beside an
// installed executable (PREFIX/bin/aar-render reads PREFIX/share/aar/), else
// in the source tree the build was configured from (build/renderer/aar-render),
// so that defaults never depend on the current directory.

#include <filesystem>
#include <string>

namespace aar {

/// PREFIX/share/aar when /proc/self/exe is PREFIX/bin/TOOL and that folder
/// holds scenes/; otherwise the configured source tree.
std::filesystem::path DataRoot();

/// DataRoot() / relative, e.g. DataFile("scenes/rig.json").
std::filesystem::path DataFile(const std::string& relative);

}  // namespace aar
