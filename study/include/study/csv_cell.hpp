// study/csv_cell.hpp: the one way a text cell enters the study's CSV files (trials.csv,
// candidates.csv, questionnaires.csv and the report's tables), all meant to be opened in
// a spreadsheet. Text that came from a participant, a design or a file name must show as
// text there: a cell that starts like a formula (=, +, -, @) is prefixed with ' (OWASP's
// rule against CSV injection), and control and bidirectional-override characters, which
// would steer a terminal or reorder what the reader sees, are written as escapes.
// Numbers the program formats itself are written as they are, never through here, so a
// negative number stays a number.
#pragma once
#include <string>
#include <string_view>

namespace study {

/// `text` with control characters (C0, DEL) and bytes that are not valid UTF-8 written as
/// \xNN, C1 controls and the bidirectional controls (U+200E, U+200F, U+202A..U+202E,
/// U+2066..U+2069) as \uNNNN; other UTF-8 is kept. Shared by every study output that shows
/// text from the inputs (the CSV cells here, the report's index.html), so such text can
/// neither steer a terminal nor reorder what the reader sees. Applying it twice changes nothing more.
std::string escapeControlText(std::string_view text);

/// `text` as a spreadsheet shows it safely: control characters (C0, DEL) and bytes that
/// are not valid UTF-8 as \xNN, C1 controls and the bidirectional controls (U+200E,
/// U+200F, U+202A..U+202E, U+2066..U+2069) as \uNNNN (so a tab or a carriage return never leads),
/// then a ' in front when the result starts with =, +, - or @. Other UTF-8 is kept. Applying it
/// twice changes nothing more.
std::string csvSafeText(std::string_view text);

/// A text cell: csvSafeText(text), quoted (RFC 4180) when it holds a comma or a quote.
std::string csvCell(std::string_view text);

}  // namespace study
