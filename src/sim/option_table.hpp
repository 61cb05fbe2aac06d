// The templated half of the option table (sim/options.hpp): each row is an OptionSpec and the
// two functions that read and write its scene field, so an option is declared in one place
// (option_table.cpp) and the manager, the checkpoint and the commands all go through the row.
#pragma once

#include <span>

#include "sim/options.hpp"
#include "sim/scene.hpp"

namespace demlab::sim {

class Writer;
class Reader;

template <int D>
struct OptionRow {
  OptionSpec spec;
  // The field's value as a double: a boolean 0 or 1, a choice its index, a real itself.
  double (*get)(const Scene<D>& s);
  // Stores x (already checked) into the field. Changes s.
  void (*set)(Scene<D>& s, double x);
};

// Returns the rows, in the order of optionSpecs(). Changes nothing.
template <int D>
std::span<const OptionRow<D>> optionTable();

// Returns v (checked) as a row's get returns it, and back. Change nothing.
double optionRaw(const OptionSpec& o, const OptionValue& v);
OptionValue optionFromRaw(const OptionSpec& o, double x);

// The options section (length-carrying, after the other sections): every Section-store option
// that differs from its default, by group and name; none differing, no section, so a scene
// keeps the bytes it had before the option existed.
inline constexpr char kOptionTag[5] = "OPTN";

// The checkpoint records (option_io.cpp).
// Writes the Header-store options, in table order, at their slot of the header. Changes w.
template <int D>
void writeHeaderOptions(Writer& w, const Scene<D>& s);
// Reads them back into s. Throws {LOAD FORMAT} on a value out of its range.
template <int D>
void readHeaderOptions(Reader& r, Scene<D>& s);
// Writes the tagged records of the groups with a tag whose options differ from the defaults
// (a group of one boolean: its tag alone, when the option is on), in table order. Changes w.
template <int D>
void writeTaggedOptions(Writer& w, const Scene<D>& s);
// Turns off the options whose record is their tag alone: a file without the tag has them off.
// Called before the tags are read. Changes s.
template <int D>
void clearTagAloneOptions(Scene<D>& s);
// Returns true if tag starts a group's tagged record, which it then reads into s (false: r
// and s unchanged). Throws {LOAD FORMAT} on a value out of its range.
template <int D>
bool readTaggedOptions(Reader& r, Scene<D>& s, const char* tag);
// Returns true and fills body with the options section's body if some Section-store option
// differs from its default; false (body unchanged) otherwise.
template <int D>
bool writeOptionSection(Writer& body, const Scene<D>& s);
// Reads an options section's body into s. Throws {LOAD SECTION} on an option this build does
// not know, {LOAD FORMAT} on a bad value.
template <int D>
void readOptionSection(Reader& body, Scene<D>& s);

}  // namespace demlab::sim
