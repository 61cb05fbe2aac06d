// The rows of the behavior registry, and the checks every type's parameters go through before
// its factory sees them.
#include "sim/behavior_registry.hpp"

#include "sim/behaviors/gravity.hpp"
#include "sim/behaviors/load.hpp"
#include "sim/behaviors/torque_ramp.hpp"

namespace demlab::sim {

const std::vector<BehaviorRow>& behaviorRegistry() {
  static const std::vector<BehaviorRow> rows{
      behaviorRow<GravityBehavior>(),
      behaviorRow<LoadBehavior>(),
      behaviorRow<TorqueRampBehavior>(),
  };
  return rows;
}

const std::vector<BehaviorTypeInfo>& behaviorTypes() {
  static const std::vector<BehaviorTypeInfo> infos = [] {
    std::vector<BehaviorTypeInfo> v;
    for (const BehaviorRow& r : behaviorRegistry()) v.push_back(r.info);
    return v;
  }();
  return infos;
}

const BehaviorRow& findBehaviorRow(std::string_view name) {
  std::string known;
  const auto& rows = behaviorRegistry();
  for (size_t k = 0; k < rows.size(); ++k) {
    if (rows[k].info.name == name) return rows[k];
    known += (k == 0 ? "" : k + 1 == rows.size() ? " or " : ", ") + rows[k].info.name;
  }
  throw Error("unknown behavior type \"" + std::string(name) + "\": must be " + known,
              {"LOOKUP", "BEHAVIORTYPE"});
}

template <int D>
std::unique_ptr<Behavior<D>> makeBehavior(std::string_view type,
                                          const std::vector<BehaviorParam>& params) {
  const BehaviorRow& row = findBehaviorRow(type);
  const std::vector<BehaviorOption>& options = row.info.options;
  for (size_t k = 0; k < params.size(); ++k) {
    const BehaviorParam& p = params[k];
    const BehaviorOption* o = nullptr;
    for (const BehaviorOption& x : options) {
      if (x.name == p.name) o = &x;
    }
    if (!o) {
      throw Error("bad option \"" + p.name + "\": a " + row.info.name + " has no such parameter",
                  {"VALUE", "OPTION"});
    }
    for (size_t j = 0; j < k; ++j) {
      if (params[j].name == p.name) {
        throw Error("bad option \"" + p.name + "\": given twice", {"VALUE", "OPTION"});
      }
    }
    switch (o->kind) {
      case BehaviorParamKind::Number:
        if (p.numbers.size() != 1 || !std::isfinite(p.numbers[0])) {
          throwBad(o->name, p.numbers.empty() ? "" : physics::formatReal(p.numbers[0]),
                   "must be a finite number");
        }
        break;
      case BehaviorParamKind::Vector:
      case BehaviorParamKind::Angular: {
        if (p.numbers.size() != 3) throwBad(o->name, "", "expected 3 numbers");
        const Vec3d v{p.numbers[0], p.numbers[1], p.numbers[2]};
        if (o->kind == BehaviorParamKind::Vector) {
          toVec<D>(v, o->name);
        } else {
          toAngular<D>(v, o->name);
        }
        break;
      }
      case BehaviorParamKind::Element:
        if (p.grain.isNull()) throwBad(o->name, "", "must name an element");
        break;
      case BehaviorParamKind::Tag:
        if (p.text.empty()) throwBad(o->name, "", "must be a tag");
        break;
    }
  }
  for (const BehaviorOption& o : options) {
    if (o.required && !findParam(params, o.name)) {
      throw Error("missing option \"" + o.name + "\": a " + row.info.name + " needs it",
                  {"VALUE", "OPTION"});
    }
  }
  if (row.info.targeted && !findParam(params, "element") == !findParam(params, "tag")) {
    throw Error("bad target: give exactly one of a grain or a tag", {"VALUE", "TARGET"});
  }
  if constexpr (D == 2) {
    return row.make2(params);
  } else {
    return row.make3(params);
  }
}

template std::unique_ptr<Behavior<2>> makeBehavior<2>(std::string_view,
                                                      const std::vector<BehaviorParam>&);
template std::unique_ptr<Behavior<3>> makeBehavior<3>(std::string_view,
                                                      const std::vector<BehaviorParam>&);

}  // namespace demlab::sim
