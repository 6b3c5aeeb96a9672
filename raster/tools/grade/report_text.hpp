// What the report writers share beyond report.hpp (not part of its interface).
#pragma once

#include <string>
#include <string_view>

namespace raster::grade {

// sanitizeText with newlines and tabs as spaces: for a table's cell or a line of the terminal.
std::string oneLine(std::string_view text);

struct GradeRun;
// "3 scenes: 1 passed, 1 failed, 1 error": the counts of a run's verdicts, for the summaries.
std::string verdictCounts(const GradeRun& run);

}  // namespace raster::grade
