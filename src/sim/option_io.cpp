// The option table's checkpoint records (sim/option_table.hpp): each option in the store its
// row names, so the options that predate the table keep their bytes and a new one needs no code
// here.
#include <algorithm>
#include <cstring>

#include "core/error.hpp"
#include "sim/option_table.hpp"
#include "sim/scene_io.hpp"

namespace demlab::sim {

namespace {

// Returns true if g's record is its tag alone: a group of one boolean (the touch flag) writes
// the tag when it is on, and nothing after it; a file without the tag has it off, whatever
// today's default (files written while it was off by default keep their meaning).
bool tagAlone(const OptionGroup& g) {
  const auto opts = groupOptions(g.name);
  return opts.size() == 1 && opts[0]->type == OptionType::Boolean;
}

// Returns x read as o's value from r (u8 for a boolean or choice, f64 for a real), checked.
double readRaw(Reader& r, const OptionSpec& o) {
  if (o.type == OptionType::Real) {
    const double x = r.f64();
    try {
      checkOption(o, x);
    } catch (const Error&) {
      Reader::bad(std::string(o.group) + " options");
    }
    return x;
  }
  const uint8_t b = r.u8();
  if (o.type == OptionType::Choice && b >= o.choices.size()) {
    Reader::bad(std::string(o.group) + " options");
  }
  return o.type == OptionType::Boolean ? (b != 0) : b;
}

// Writes x as o's value (u8 for a boolean or choice, f64 for a real). Changes w.
void writeRaw(Writer& w, const OptionSpec& o, double x) {
  if (o.type == OptionType::Real) {
    w.f64(x);
  } else {
    w.u8(static_cast<uint8_t>(x));
  }
}

}  // namespace

template <int D>
void writeHeaderOptions(Writer& w, const Scene<D>& s) {
  for (const OptionRow<D>& row : optionTable<D>()) {
    if (row.spec.store == OptionStore::Header) writeRaw(w, row.spec, row.get(s));
  }
}

template <int D>
void readHeaderOptions(Reader& r, Scene<D>& s) {
  for (const OptionRow<D>& row : optionTable<D>()) {
    if (row.spec.store == OptionStore::Header) row.set(s, readRaw(r, row.spec));
  }
}

template <int D>
void writeTaggedOptions(Writer& w, const Scene<D>& s) {
  for (const OptionGroup& g : optionGroups()) {
    if (*g.tag == 0) continue;
    const bool alone = tagAlone(g);
    bool write = false;
    for (const OptionRow<D>& row : optionTable<D>()) {
      if (row.spec.group != g.name) continue;
      const double x = row.get(s);
      write |= alone ? x != 0 : x != optionRaw(row.spec, row.spec.def);
    }
    if (!write) continue;
    w.bytes.append(g.tag, 4);
    if (alone) continue;
    for (const OptionRow<D>& row : optionTable<D>()) {
      if (row.spec.group == g.name) writeRaw(w, row.spec, row.get(s));
    }
  }
}

template <int D>
void clearTagAloneOptions(Scene<D>& s) {
  for (const OptionGroup& g : optionGroups()) {
    if (*g.tag == 0 || !tagAlone(g)) continue;
    for (const OptionRow<D>& row : optionTable<D>()) {
      if (row.spec.group == g.name) row.set(s, 0.0);
    }
  }
}

template <int D>
bool readTaggedOptions(Reader& r, Scene<D>& s, const char* tag) {
  for (const OptionGroup& g : optionGroups()) {
    if (*g.tag == 0 || std::memcmp(tag, g.tag, 4) != 0) continue;
    for (const OptionRow<D>& row : optionTable<D>()) {
      if (row.spec.group == g.name) row.set(s, tagAlone(g) ? 1.0 : readRaw(r, row.spec));
    }
    return true;
  }
  return false;
}

template <int D>
bool writeOptionSection(Writer& body, const Scene<D>& s) {
  std::vector<const OptionRow<D>*> differ;
  for (const OptionRow<D>& row : optionTable<D>()) {
    if (row.spec.store == OptionStore::Section && row.get(s) != optionRaw(row.spec, row.spec.def))
      differ.push_back(&row);
  }
  if (differ.empty()) return false;
  // By group and name, with the value's type; a choice by its name: a later build may reorder
  // the table or a choice list without misreading this one.
  body.list(differ, [&](const OptionRow<D>* row) {
    body.str(std::string(row->spec.group));
    body.str(std::string(row->spec.name));
    body.u8(static_cast<uint8_t>(row->spec.type));
    const double x = row->get(s);
    if (row->spec.type == OptionType::Choice) {
      body.str(std::string(row->spec.choices[static_cast<size_t>(x)]));
    } else {
      writeRaw(body, row->spec, x);
    }
  });
  return true;
}

template <int D>
void readOptionSection(Reader& body, Scene<D>& s) {
  const size_t n = body.count(18);
  for (size_t k = 0; k < n; ++k) {
    const std::string group = body.str(), name = body.str();
    const auto rows = optionTable<D>();
    const auto it = std::find_if(rows.begin(), rows.end(), [&](const OptionRow<D>& r) {
      return r.spec.group == group && r.spec.name == name;
    });
    if (it == rows.end()) {
      throw Error("can't load a checkpoint with the option \"" + group + " -" + name +
                      "\": it was written by a later demlab",
                  {"LOAD", "SECTION"});
    }
    const OptionSpec& o = it->spec;
    if (body.u8() != static_cast<uint8_t>(o.type)) Reader::bad(group + " options");
    if (o.type == OptionType::Choice) {
      const std::string word = body.str();
      const auto c = std::find(o.choices.begin(), o.choices.end(), word);
      if (c == o.choices.end()) Reader::bad(group + " options");
      it->set(s, static_cast<double>(c - o.choices.begin()));
    } else {
      it->set(s, readRaw(body, o));
    }
  }
}

template void writeHeaderOptions<2>(Writer&, const Scene<2>&);
template void writeHeaderOptions<3>(Writer&, const Scene<3>&);
template void readHeaderOptions<2>(Reader&, Scene<2>&);
template void readHeaderOptions<3>(Reader&, Scene<3>&);
template void writeTaggedOptions<2>(Writer&, const Scene<2>&);
template void writeTaggedOptions<3>(Writer&, const Scene<3>&);
template void clearTagAloneOptions<2>(Scene<2>&);
template void clearTagAloneOptions<3>(Scene<3>&);
template bool readTaggedOptions<2>(Reader&, Scene<2>&, const char*);
template bool readTaggedOptions<3>(Reader&, Scene<3>&, const char*);
template bool writeOptionSection<2>(Writer&, const Scene<2>&);
template bool writeOptionSection<3>(Writer&, const Scene<3>&);
template void readOptionSection<2>(Reader&, Scene<2>&);
template void readOptionSection<3>(Reader&, Scene<3>&);

}  // namespace demlab::sim
