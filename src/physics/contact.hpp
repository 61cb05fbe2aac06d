// The per-contact interface between the simulation's contact pass and the contact laws:
// what a law reads (ContactGeometry, ContactKinematics, the pair's PairParams and its
// TangentialHistory) and what it returns (ContactForce).
//
// Conventions. A contact is between A and B (for a grain and a wall: A the grain, B the wall).
// The normal points from A towards B. relativeVelocity is B's material velocity at the contact
// point minus A's, so its normal component vn = v.n is negative while they approach.
// The force returned acts on B at the contact point; A receives its opposite. Torques are the
// sim's: r x F with r from each centre to the point.
//
// How the sim calls a law. Resolve it ONCE per material pair or batch, never per contact:
//   ContactLawFn<D> law = contactLawFor<D>(params.law);      // one row of the law table
//   for (each contact) f = law(params, geometry, kinematics, history, dt);
// or, for a loop templated on the law, call the inline linearContact / hertzMindlinContact
// (law_linear.hpp, law_hertz_mindlin.hpp) directly. evaluateContact() switches per call and is
// meant for tests and one-off calls.
//
// Attractive forces: the normal force, spring plus damping, is clamped at >= 0. At separation
// the damping term can exceed the spring term (the grains part faster than the spring relaxes),
// and an unclamped law would then pull the grains together. LIGGGHTS keeps that pull unless
// "limitForce on" is given; demlab always cuts it off. Contact counts do not depend on this
// (they are geometric); trajectories match LIGGGHTS run with limitForce on.
//
// Velocity to pass: either the half-step velocity v(n+1/2) that moved the positions (plain
// velocity Verlet, as LIGGGHTS passes it; set velocityLag = 0.5) or a velocity synchronized
// with the positions (velocityLag = 0). The shear spring gains the displacement the positions
// made, the half-step velocity times dt: given, or recovered from the synchronized ones
// (TangentialHistory::drift, tangential.hpp).
//
// Energy. Per step each law reports the elastic energy its springs hold after the step, the
// energy dissipated during the step by damping and by Coulomb sliding, and the stiffening work
// springWork (Hertz-Mindlin's tangential spring), so that over a contact's life
//   work done on the bodies by the contact
//     = -(elastic energy now) - sum(dampingLoss + frictionLoss) + sum(springWork).
// The normal damping loss is charged at the normal velocity of the force time (see
// velocityLag), so the normal ledger is second order in dt: the unit tests close head-on
// impacts to 3e-5 of the kinetic energy at dt = tc/200 with half-step velocities. The
// tangential spring's losses are booked by the trapezoid identity over the step's displacement,
// the integrator's own work (tangential.hpp): second order as well.
// Where the normal force is clamped at 0, the spring energy that disappears without doing work
// is booked as damping loss (it is what the damper took).
#pragma once

#include <cmath>
#include <limits>

#include "core/math.hpp"
#include "physics/pair_params.hpp"

namespace demlab::physics {

template <int D>
struct ContactGeometry {
  VecD<D> normal;  // unit, from A towards B
  Real overlap;    // > 0 when touching (m)
  VecD<D> point;   // contact point (world): the middle of the overlap along the normal
};

template <int D>
struct ContactKinematics {
  VecD<D> relativeVelocity;  // B's material velocity at the contact point minus A's (m/s)
  Real effectiveMass;        // m_a m_b / (m_a + m_b); against a wall (infinite mass): m_grain
  Real effectiveRadius;      // r_a r_b / (r_a + r_b); against a wall (flat): r_grain
  // How many steps relativeVelocity lags the force time, for the damping ledger only: 0 when
  // the sim passes velocities synchronized with the positions (v(t+dt/2) + a(t) dt/2), 0.5
  // for plain velocity Verlet's half-step velocities v(t+dt/2). The damper's loss is charged
  // at vn + velocityLag dt Fn/m*, the velocity the force's own kick leads to.
  Real velocityLag = 0;
};

// The tangential spring of one contact, kept per pair (InstanceInteractionManager) from the
// step the contact closes to the step it opens, in the pair's (A, B) orientation: if the sim
// swaps A and B it must negate the spring. spring is the spring's elongation (m): B's
// tangential displacement relative to A, kept in the current tangent plane; the spring force on
// B is -kt spring. A new contact starts from zero.
// drift: with synchronized velocities, the relative velocity of the half-step velocities that
// moved the positions in the last step, recovered per contact (tangential.hpp,
// driftDisplacement); NaN where there is none yet (a new contact, a scene saved before it was
// kept, half-step velocities). A history with a zero spring and no drift is empty: the contact
// pools keep none. damperImpulse, damperPending: with the drift, the last step's normal damper
// force times dt, and the part of its loss still to book once the next drift velocity is known
// (tangential.hpp, damperCatchUp); zero otherwise.
template <int D>
struct TangentialHistory {
  VecD<D> spring = VecD<D>::Zero();
  VecD<D> drift = VecD<D>::Constant(std::numeric_limits<Real>::quiet_NaN());
  Real damperImpulse = 0;
  Real damperPending = 0;
  bool empty() const { return spring.squaredNorm() == 0 && std::isnan(drift[0]); }
};

template <int D>
struct ContactForce {
  VecD<D> force;       // acting on B at the point; A receives -force (N)
  Real elasticEnergy;  // energy stored in the contact's springs after this step (J)
  Real dampingLoss;    // energy dissipated by viscous damping during this step (J, >= 0)
  Real frictionLoss;   // energy dissipated by Coulomb sliding during this step (J, >= 0)
  // Energy put into the tangential spring during this step by the change of its stiffness
  // (J, signed): Hertz-Mindlin's kt grows with the overlap, so a loaded spring gains energy
  // from no force as the grains press in and loses it as they part; 0 for the linear law.
  // The per-contact ledger: elasticEnergy(now) - elasticEnergy(before) = work done on the
  // contact by the bodies + springWork - dampingLoss - frictionLoss.
  Real springWork;
  // True when the pair touches and the law clamped its normal force to zero (a damped force
  // cut off as the grains part): the touch correction's event (sim/touch.hpp).
  bool cutOff = false;
};

// A contact law: returns the force on B and the energy figures for one contact and one step of
// length dt; changes *history (when not null) to the spring after this step. history == nullptr
// means the scene keeps no tangential history (no friction): the force is then purely normal.
template <int D>
using ContactLawFn = ContactForce<D> (*)(const PairParams& params, const ContactGeometry<D>& g,
                                         const ContactKinematics<D>& k,
                                         TangentialHistory<D>* history, Real dt);

// Returns the plain function pointer of `law` for dimension D (2 or 3), from the law table
// (contact_laws.cpp: one row per law). Throws demlab::Error {LOOKUP LAW} for an unknown law.
template <int D>
ContactLawFn<D> contactLawFor(LawKind law);

// Returns contactLawFor<D>(params.law)(params, g, k, history, dt); changes *history as the law
// does. Switches on the law at every call: for tests and one-off calls, not for the force loop.
template <int D>
ContactForce<D> evaluateContact(const PairParams& params, const ContactGeometry<D>& g,
                                const ContactKinematics<D>& k, TangentialHistory<D>* history,
                                Real dt);

}  // namespace demlab::physics
