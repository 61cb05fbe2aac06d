#include "cmd/time_vector.hpp"

#include <cmath>

#include "cmd/words.hpp"

namespace demlab::cmd {

PipeType timeVector(bool isSpin) {
  return custom(isSpin ? "spin of expressions" : "vector of expressions",
                [isSpin](std::string_view w, const Param& p, const Context& c) -> std::any {
                  std::vector<std::string> parts = splitList(w);
                  std::size_t n =
                      isSpin ? (c.dimension() == 2 ? 1 : 3) : std::size_t(c.dimension());
                  if (parts.size() != n) {
                    throw Error("bad " + p.name + " \"" + std::string(w) + "\": expected " +
                                    std::to_string(n) + " numbers or expressions in $t but got " +
                                    std::to_string(parts.size()),
                                {"VALUE", codeWord(p.name)});
                  }
                  return parts;
                });
}

void timeComponents(Call& c, const std::string& opt, bool isSpin, const TimeBound& bound,
                    sim::Vec3d& constant, std::array<sim::TimeFunction, 3>& fns, bool valueNow) {
  Session& s = session(c);
  const auto& parts = c.get<std::vector<std::string>>(opt);
  for (std::size_t k = 0; k < parts.size(); ++k) {
    std::size_t axis = isSpin && parts.size() == 1 ? 2 : k;
    double x;
    if (readReal(parts[k], x)) {
      if (!std::isfinite(x)) c.bad(opt, "must be finite");
      constant[axis] = x;
    } else {
      if (!s.timeFunction)
        throw Error("bad " + opt + ": expressions need a Tcl interpreter",
                    {"VALUE", codeWord(opt)});
      double first = 0;
      fns[axis] = s.timeFunction(parts[k], opt, s.scene().time(), bound, &first);
      if (valueNow) constant[axis] = first;
    }
  }
}

}  // namespace demlab::cmd
