#include "io/pvd_series.hpp"

#include <fmt/format.h>

#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "io/write_file.hpp"

namespace biota::io {

void update_pvd(const std::string& pvd_path, long long step, double time,
                const std::string& relative_file) {
  // Entries are keyed by step, recorded in the 'part'-free 'name' attribute we write ourselves.
  std::map<long long, std::string> entries;
  {
    std::ifstream in(pvd_path);
    std::string line;
    const std::regex re(R"(<DataSet step=\"(-?\d+)\".*/>)");
    std::smatch m;
    while (std::getline(in, line))
      if (std::regex_search(line, m, re)) entries[std::stoll(m[1])] = m[0];
  }
  entries.erase(entries.lower_bound(step), entries.end());
  entries[step] =
      fmt::format(R"(<DataSet step="{}" timestep="{:.17g}" group="" part="0" file="{}"/>)", step,
                  time, relative_file);
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n";
  for (const auto& [s, e] : entries) out << "  " << e << "\n";
  out << "</Collection>\n</VTKFile>\n";
  write_text_file(pvd_path, out.str());
}

}  // namespace biota::io
