// Pipes: how one word of a call becomes one typed, checked value (thesis 12.3.3). A PipeType is
// declared with the parameter (its kind, unit, range, choices) and does the parameter's part of
// the check phase: conversion from the word, then the range or membership check. Every failure
// is a demlab::Error in Tcl's wording with code {VALUE <PARAM>}; nothing is changed by a pipe.
//
// Values travel as std::any: double (real), std::int64_t (integer), bool (boolean, flag),
// std::string (text, name, choice), std::vector<double> (vector, reals), or whatever a custom
// pipe returns.
#pragma once

#include <any>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace demlab::cmd {

struct Param;
struct Context;

struct PipeType {
  enum class Kind { Real, Int, Bool, Text, Name, Choice, Vector, Reals, Ints, Custom };
  Kind kind = Kind::Text;
  std::string label;             // the type as help shows it: real, vector, material...
  std::string unit;              // SI unit shown in help ("m", "kg/m^3"); empty if none
  std::optional<double> lo, hi;  // range of reals and integers (and of vector components)
  bool loOpen = false, hiOpen = false;
  int length = 0;                    // Vector: number of components; 0 means the dimension
  bool list = false;                 // Text: the word must be a well-formed Tcl list
  std::vector<std::string> choices;  // Choice: the accepted words (unique prefixes accepted)
  // Custom: converts and checks the word; may read the context (names of existing objects).
  std::function<std::any(std::string_view word, const Param& p, const Context& ctx)> custom;
  // Completion candidates that depend on the scene (names of materials, tags...).
  using Candidates = std::function<std::vector<std::string>(const Context& ctx)>;
  Candidates candidates;

  // Builders. Each returns a copy with the property set.
  PipeType withUnit(std::string u) const {
    PipeType t = *this;
    t.unit = std::move(u);
    return t;
  }
  PipeType positive() const { return min(0, true); }
  PipeType nonNegative() const { return min(0, false); }
  PipeType min(double v, bool open = false) const {
    PipeType t = *this;
    t.lo = v;
    t.loOpen = open;
    return t;
  }
  PipeType max(double v, bool open = false) const {
    PipeType t = *this;
    t.hi = v;
    t.hiOpen = open;
    return t;
  }
  PipeType range(double a, double b) const { return min(a).max(b); }
  // A text that the command reads as a list: a word that is not one is refused in the check
  // phase, naming the parameter, instead of where the command splits it.
  PipeType asList() const {
    PipeType t = *this;
    t.list = true;
    return t;
  }
  PipeType complete(std::function<std::vector<std::string>(const Context&)> f) const {
    PipeType t = *this;
    t.candidates = std::move(f);
    return t;
  }

  // Returns the range as help shows it ("> 0", "0..1", ">= 1"), or "" if unbounded.
  std::string constraint() const;
};

// The pipe kinds. vector(): as many reals as the simulation has dimensions (Context::dimension).
PipeType real();
PipeType integer();
PipeType boolean();
PipeType text(std::string label = "string");
PipeType name(std::string label = "name");  // object names: a letter or "_" first
PipeType choice(std::vector<std::string> words, std::string label = "");
PipeType vector(int length = 0);
PipeType reals();  // a list of any number of reals
PipeType ints();   // a list of any number of integers
PipeType custom(std::string label,
                std::function<std::any(std::string_view, const Param&, const Context&)> fn);

// The check phase of one word: returns its typed value or throws demlab::Error {VALUE <PARAM>}.
std::any convertWord(std::string_view word, const Param& p, const Context& ctx);

// Returns the full choice that `word` names (exact, or unique prefix). Throws demlab::Error
// with code {VALUE <PARAM>}: `bad <what> "x": must be a, b, or c` (ambiguous: `ambiguous ...`).
const std::string& matchChoice(std::string_view word, const std::vector<std::string>& choices,
                               std::string_view what, std::vector<std::string> code);

}  // namespace demlab::cmd
