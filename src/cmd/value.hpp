// cmd::Value: what a command returns, as a small tree (empty, boolean, integer, real, string,
// list, dict, a flat array of reals that reads as a list or as a list of fixed-size tuples, a
// flat array of integers (ids) that reads as a list, and binary bytes).
// The command layer knows nothing of Tcl; the binding (src/tcl) turns a Value into Tcl_Obj
// without going through strings, so reals keep every bit and bulk queries stay cheap.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace demlab::cmd {

struct Value;
using List = std::vector<Value>;
using Dict = std::vector<std::pair<std::string, Value>>;  // insertion order is kept

// A flat array of reals. stride 0: a plain list of numbers; stride k > 0: a list of k-lists
// (positions of N elements in 3D are N 3-lists).
struct Reals {
  std::vector<double> data;
  int stride = 0;
};

// A flat array of integers that reads as a list: the ids a command made (half a million
// elements, millions of bonds), which the binding hands to Tcl without an object each.
struct Ints {
  std::vector<std::int64_t> data;
};

// Binary data (an image's bytes): a Tcl byte array, no text conversion.
struct Bytes {
  std::vector<std::uint8_t> data;
};

struct Value {
  std::variant<std::monostate, bool, std::int64_t, double, std::string, List, Dict, Reals, Ints,
               Bytes>
      v;

  Value() = default;
  Value(bool b) : v(b) {}
  Value(int i) : v(std::int64_t(i)) {}
  Value(long i) : v(std::int64_t(i)) {}
  Value(long long i) : v(std::int64_t(i)) {}
  Value(unsigned i) : v(std::int64_t(i)) {}
  Value(unsigned long i) : v(std::int64_t(i)) {}
  Value(unsigned long long i) : v(std::int64_t(i)) {}
  Value(double d) : v(d) {}
  Value(const char* s) : v(std::string(s)) {}
  Value(std::string s) : v(std::move(s)) {}
  Value(List l) : v(std::move(l)) {}
  Value(Dict d) : v(std::move(d)) {}
  Value(Reals r) : v(std::move(r)) {}
  Value(Ints i) : v(std::move(i)) {}
  Value(Bytes b) : v(std::move(b)) {}

  bool empty() const { return std::holds_alternative<std::monostate>(v); }
};

// Returns a Reals list of the n values at p (stride 0).
inline Value realList(const double* p, std::size_t n) {
  return Reals{{p, p + n}, 0};
}

// Returns a Reals list of one vector of any Eigen-like type with size() and operator[].
template <class V>
Value vectorValue(const V& x) {
  Reals r;
  r.data.reserve(std::size_t(x.size()));
  for (int i = 0; i < int(x.size()); ++i) r.data.push_back(double(x[i]));
  return r;
}

// Returns the plain-text form of v, as Tcl would print it (used by tests and the docs; the
// binding never goes through it).
std::string toString(const Value& v);

}  // namespace demlab::cmd
