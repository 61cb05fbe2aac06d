#include "cmd/pipe.hpp"

#include <cmath>

#include "cmd/command.hpp"
#include "cmd/words.hpp"
#include "core/error.hpp"
#include "core/name_lookup.hpp"

namespace demlab::cmd {

namespace {

PipeType make(PipeType::Kind k, std::string label) {
  PipeType t;
  t.kind = k;
  t.label = std::move(label);
  return t;
}

std::string num(double x) {
  std::string s = formatReal(x);
  if (s.size() > 2 && s.substr(s.size() - 2) == ".0") s.resize(s.size() - 2);
  return s;
}

[[noreturn]] void badValue(const Param& p, std::string_view word, const std::string& why) {
  throw Error("bad " + p.name + " \"" + std::string(word) + "\": " + why,
              {"VALUE", codeWord(p.name)});
}

// Returns why x is outside the type's range ("must be a positive number"), or "" if inside.
std::string rangeFault(const PipeType& t, double x, bool integral) {
  const char* what = integral ? "integer" : "number";
  bool below = t.lo && (t.loOpen ? !(x > *t.lo) : !(x >= *t.lo));
  bool above = t.hi && (t.hiOpen ? !(x < *t.hi) : !(x <= *t.hi));
  if (!below && !above) return "";
  if (t.lo && t.hi && !t.loOpen && !t.hiOpen)
    return std::string("must be between ") + num(*t.lo) + " and " + num(*t.hi);
  if (t.lo && t.hi) {
    return std::string("must be ") + (t.loOpen ? "> " : ">= ") + num(*t.lo) + " and " +
           (t.hiOpen ? "< " : "<= ") + num(*t.hi);
  }
  if (t.lo && *t.lo == 0)
    return std::string("must be a ") + (t.loOpen ? "positive " : "non-negative ") + what;
  if (t.lo) return std::string("must be ") + (t.loOpen ? "> " : ">= ") + num(*t.lo);
  return std::string("must be ") + (t.hiOpen ? "< " : "<= ") + num(*t.hi);
}

// Returns x, read from word, once it is finite and in p's range (the error names word).
double checkedReal(double x, std::string_view word, const Param& p) {
  if (!std::isfinite(x)) badValue(p, word, "must be a finite number");
  std::string fault = rangeFault(p.type, x, false);
  if (!fault.empty()) badValue(p, word, fault);
  return x;
}

// Returns i, read from word, once it is in p's range (the error names word).
std::int64_t checkedInt(std::int64_t i, std::string_view word, const Param& p) {
  std::string fault = rangeFault(p.type, double(i), true);
  if (!fault.empty()) badValue(p, word, fault);
  return i;
}

double toReal(std::string_view word, const Param& p) {
  double x;
  if (!readReal(word, x)) badValue(p, word, "expected floating-point number");
  return checkedReal(x, word, p);
}

std::int64_t toInt(std::string_view word, const Param& p) {
  std::int64_t i;
  if (!readInt(word, i)) badValue(p, word, "expected integer");
  return checkedInt(i, word, p);
}

// Returns the number of item, one of the numbers of p's list or vector word; a word that is not
// a number is named with the whole list (`bad position "0 abc 0": expected floating-point
// number but got "abc"`), range faults as a scalar's.
double itemReal(std::string_view item, std::string_view word, const Param& p) {
  double x;
  if (!readReal(item, x)) {
    badValue(p, word, "expected floating-point number but got \"" + std::string(item) + "\"");
  }
  return checkedReal(x, item, p);
}

std::int64_t itemInt(std::string_view item, std::string_view word, const Param& p) {
  std::int64_t i;
  if (!readInt(item, i)) badValue(p, word, "expected integer but got \"" + std::string(item) + "\"");
  return checkedInt(i, item, p);
}

}  // namespace

std::string PipeType::constraint() const {
  if (lo && hi && !loOpen && !hiOpen) return num(*lo) + ".." + num(*hi);
  if (lo && hi) return num(*lo) + (loOpen ? " < x " : " <= x ") + (hiOpen ? "< " : "<= ") + num(*hi);
  if (lo) return std::string(loOpen ? "> " : ">= ") + num(*lo);
  if (hi) return std::string(hiOpen ? "< " : "<= ") + num(*hi);
  return "";
}

PipeType real() {
  return make(PipeType::Kind::Real, "real");
}
PipeType integer() {
  return make(PipeType::Kind::Int, "integer");
}
PipeType boolean() {
  return make(PipeType::Kind::Bool, "boolean");
}
PipeType text(std::string label) {
  return make(PipeType::Kind::Text, std::move(label));
}
PipeType name(std::string label) {
  return make(PipeType::Kind::Name, std::move(label));
}
PipeType choice(std::vector<std::string> words, std::string label) {
  PipeType t = make(PipeType::Kind::Choice, label.empty() ? joinList(words) : std::move(label));
  t.choices = std::move(words);
  return t;
}
PipeType vector(int length) {
  PipeType t = make(PipeType::Kind::Vector, "vector");
  t.length = length;
  return t;
}
PipeType reals() {
  return make(PipeType::Kind::Reals, "list of reals");
}
PipeType ints() {
  return make(PipeType::Kind::Ints, "list of integers");
}
PipeType custom(std::string label,
                std::function<std::any(std::string_view, const Param&, const Context&)> fn) {
  PipeType t = make(PipeType::Kind::Custom, std::move(label));
  t.custom = std::move(fn);
  return t;
}

const std::string& matchChoice(std::string_view word, const std::vector<std::string>& choices,
                               std::string_view what, std::vector<std::string> code) {
  const std::string* hit = nullptr;
  int prefixHits = 0;
  for (const std::string& c : choices) {
    if (c == word) return c;
    if (!word.empty() && c.compare(0, word.size(), word) == 0) {
      hit = &c;
      ++prefixHits;
    }
  }
  if (prefixHits == 1) return *hit;
  throw Error(std::string(prefixHits > 1 ? "ambiguous " : "bad ") + std::string(what) + " \"" +
                  std::string(word) + "\": must be " + alternatives(choices),
              std::move(code));
}

namespace {

std::any convertChecked(std::string_view word, const Param& p, const Context& ctx);

}  // namespace

std::any convertWord(std::string_view word, const Param& p, const Context& ctx) {
  try {
    return convertChecked(word, p, ctx);
  } catch (const Error& e) {
    // A word that is not a well-formed list ("{"): Tcl's message alone does not say which
    // word; wherever the pipe split it (a vector, a region, a custom list), name it here.
    const auto& code = e.code();
    if (code.size() == 3 && code[1] == "VALUE" && code[2] == "LIST") badValue(p, word, e.what());
    throw;
  }
}

namespace {

// Returns the typed value of word for p (convertWord without the naming of list errors).
std::any convertChecked(std::string_view word, const Param& p, const Context& ctx) {
  const PipeType& t = p.type;
  switch (t.kind) {
    case PipeType::Kind::Real:
      return toReal(word, p);
    case PipeType::Kind::Int:
      return toInt(word, p);
    case PipeType::Kind::Bool: {
      bool b;
      if (!readBool(word, b)) badValue(p, word, "expected boolean value");
      return b;
    }
    case PipeType::Kind::Text:
      if (t.list) splitList(word);  // throws {VALUE LIST}, which convertWord names
      return std::string(word);
    case PipeType::Kind::Name:
      try {
        checkObjectName(p.name, word);
      } catch (const Error& e) {
        // Keep the reason, word it for this parameter: bad name "7up": must start with ...
        std::string why = e.what();
        auto colon = why.find("\": ");
        why = colon == std::string::npos ? why : why.substr(colon + 3);
        badValue(p, word, why);
      }
      return std::string(word);
    case PipeType::Kind::Choice:
      return matchChoice(word, t.choices, p.name, {"VALUE", codeWord(p.name)});
    case PipeType::Kind::Vector: {
      std::vector<std::string> items = splitList(word);
      std::size_t n = std::size_t(t.length > 0 ? t.length : ctx.dimension());
      if (items.size() != n) {
        badValue(p, word,
                 "expected a vector of " + std::to_string(n) + " numbers but got " +
                     std::to_string(items.size()));
      }
      std::vector<double> out;
      for (const std::string& s : items) out.push_back(itemReal(s, word, p));
      return out;
    }
    case PipeType::Kind::Reals:
    case PipeType::Kind::Ints: {
      std::vector<std::string> items = splitList(word);
      if (t.kind == PipeType::Kind::Ints) {
        std::vector<std::int64_t> out;
        for (const std::string& s : items) out.push_back(itemInt(s, word, p));
        return out;
      }
      std::vector<double> out;
      for (const std::string& s : items) out.push_back(itemReal(s, word, p));
      return out;
    }
    case PipeType::Kind::Custom:
      return t.custom(word, p, ctx);
  }
  return {};
}

}  // namespace

}  // namespace demlab::cmd
