// Tcl's lexical conventions, for a command layer that does not link Tcl: list splitting and
// quoting, numbers and booleans as Tcl reads them, and Tcl's wording of the usual errors. The
// binding replaces the list splitter by Tcl's own (setListSplitter), so scripts see exactly
// Tcl's rules; the built-in one follows Tcl_SplitList for braces, quotes and backslashes.
#pragma once

#include <cstdint>
#include <functional>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace demlab::cmd {

// Returns the elements of the Tcl list `text`. Throws demlab::Error {VALUE LIST} with Tcl's
// message (`unmatched open brace in list`, ...) when it is not a well-formed list.
std::vector<std::string> splitList(std::string_view text);

// Replaces the list splitter used by splitList (nullptr restores the built-in one). The
// splitter returns false and fills `error` when the text is not a list. Changes global state:
// call it once, at load time.
using ListSplitter =
    std::function<bool(std::string_view, std::vector<std::string>&, std::string& error)>;
void setListSplitter(ListSplitter splitter);

// Returns s quoted as one Tcl list element (braces or backslashes only where needed).
std::string quoteElement(std::string_view s);

// Returns the words joined into one Tcl list.
std::string joinList(const std::vector<std::string>& words);

// Returns the real number `text` reads as under Tcl's rules (surrounding white space allowed;
// decimal, exponent, Inf, NaN, 0x integers). Returns false when it is not a number; changes only
// `out`.
bool readReal(std::string_view text, double& out);

// Returns the integer `text` reads as (decimal, 0x, 0o, 0b, optional sign, surrounding white
// space). Returns false when it is not an integer or does not fit in 64 bits.
bool readInt(std::string_view text, std::int64_t& out);

// Returns the boolean `text` reads as (1/0, true/false, yes/no, on/off, unique prefixes as Tcl
// allows, any case, or any integer). Returns false when it is not a boolean.
bool readBool(std::string_view text, bool& out);

// Returns a real formatted the way Tcl prints doubles: the shortest string that reads back
// to the same bits, always with a "." or an exponent ("1.0", "2.5e-05").
std::string formatReal(double x);

// Returns "a", "a or b", "a, b, or c": Tcl's way of listing alternatives in error messages.
std::string alternatives(const std::vector<std::string>& items, std::string_view conj = "or");

// Returns the width help text is wrapped to: $COLUMNS when it is a number, else the terminal's
// width when standard output is one, else 80; at least 40. Changes nothing.
std::size_t helpWidth();

// Returns text filled into lines of at most width characters (a word longer than a line stands
// alone), each starting with indent spaces, the first with first spaces instead (a row's
// left column is already there); every line ends in "\n". Changes nothing.
std::string wrapText(std::string_view text, std::size_t width, std::size_t indent,
                     std::size_t first);

// Returns one row of a help table: left padded to leftWidth after four spaces, then right
// wrapped in its own column; when that column would be narrower than 30 characters, right
// starts on the next line, indented eight. Changes nothing.
std::string helpRow(std::string_view left, std::size_t leftWidth, std::string_view right,
                    std::size_t width);

// Returns the word in upper case, with "-" removed: the error-code word for a parameter name
// ("radius" -> "RADIUS", "-time-step" -> "TIMESTEP").
std::string codeWord(std::string_view name);

}  // namespace demlab::cmd
