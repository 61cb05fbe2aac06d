// The law table: one row per contact law. A new law is a new header with its inline contact
// function and one row here (and a LawKind value).
#include <array>
#include <string>

#include "core/error.hpp"
#include "physics/contact.hpp"
#include "physics/law_hertz_mindlin.hpp"
#include "physics/law_linear.hpp"

namespace demlab::physics {

namespace {

struct LawRow {
  LawKind kind;
  ContactLawFn<2> fn2;
  ContactLawFn<3> fn3;
};

constexpr std::array kLaws{
    LawRow{LawKind::Linear, &linearContact<2>, &linearContact<3>},
    LawRow{LawKind::HertzMindlin, &hertzMindlinContact<2>, &hertzMindlinContact<3>},
};

}  // namespace

template <int D>
ContactLawFn<D> contactLawFor(LawKind law) {
  for (const LawRow& row : kLaws) {
    if (row.kind == law) {
      if constexpr (D == 2) {
        return row.fn2;
      } else {
        return row.fn3;
      }
    }
  }
  throw Error("unknown contact law " + std::to_string(static_cast<int>(law)), {"LOOKUP", "LAW"});
}

template <int D>
ContactForce<D> evaluateContact(const PairParams& params, const ContactGeometry<D>& g,
                                const ContactKinematics<D>& k, TangentialHistory<D>* history,
                                Real dt) {
  switch (params.law) {
    case LawKind::Linear:
      return linearContact<D>(params, g, k, history, dt);
    case LawKind::HertzMindlin:
      return hertzMindlinContact<D>(params, g, k, history, dt);
  }
  return contactLawFor<D>(params.law)(params, g, k, history, dt);
}

template ContactLawFn<2> contactLawFor<2>(LawKind);
template ContactLawFn<3> contactLawFor<3>(LawKind);
template ContactForce<2> evaluateContact<2>(const PairParams&, const ContactGeometry<2>&,
                                            const ContactKinematics<2>&, TangentialHistory<2>*,
                                            Real);
template ContactForce<3> evaluateContact<3>(const PairParams&, const ContactGeometry<3>&,
                                            const ContactKinematics<3>&, TangentialHistory<3>*,
                                            Real);

}  // namespace demlab::physics
