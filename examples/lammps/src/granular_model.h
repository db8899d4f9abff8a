// The granular contact model shared by pair_style granular/rollslide and fix
// wall/gran/rollslide: the coefficients of LAMMPS' granular keywords (the supported subset), their
// parsing, the rollslide library model they make, and the normal force as LAMMPS 20220106
// computes it (with the normal spring's energy and the normal dashpot's force, which the energy
// compute needs).
#ifndef ROLLSLIDE_GRANULAR_MODEL_H
#define ROLLSLIDE_GRANULAR_MODEL_H

#include "rollslide.h"

#include <cmath>
#include <functional>
#include <string>

namespace LAMMPS_NS {

class LAMMPS;

namespace granular {

// DMT: Hertz's elastic force minus the pull-off force 4 pi coh R_eff (coh: the cohesion energy
// density); JKR: the force of the JKR contact radius a (see jkr_contact_radius), which persists
// beyond touching (negative overlap) until pull-off. Both with the normal coefficient 4/3 E* as
// hertz/material's.
enum Normal { HOOKE, HERTZ, HERTZ_MATERIAL, DMT, JKR };
enum Damping { VELOCITY, MASS_VELOCITY, VISCOELASTIC, TSUJI };
// LAMMPS' tangential models. linear_nohistory: a dashpot clipped at the friction limit (no
// spring: k_t = 0 in the library's linear law); linear_history: a spring of constant k_t;
// the mindlin family: k_t = kt a (a = sqrt(delta R_eff), the contact radius), the spring
// storing a displacement (mindlin, mindlin_rescale) or its elastic force (mindlin/force,
// mindlin_rescale/force), the _rescale ones scaling it down when a falls (unloading).
enum Tangential {
  LINEAR_NOHISTORY,
  LINEAR_HISTORY,
  MINDLIN,
  MINDLIN_RESCALE,
  MINDLIN_FORCE,
  MINDLIN_RESCALE_FORCE
};
// Whether a tangential model scales k_t with the contact radius (the mindlin family).
inline bool is_mindlin(int tangential)
{
  static_assert(MINDLIN_RESCALE > MINDLIN && MINDLIN_FORCE > MINDLIN &&
                    MINDLIN_RESCALE_FORCE > MINDLIN && LINEAR_HISTORY < MINDLIN &&
                    LINEAR_NOHISTORY < MINDLIN,
                "the mindlin family closes the list");
  return tangential >= MINDLIN;    // one compare: the pair style's hot loop asks per contact
}
// The library's sliding history of a tangential model (RSL_SLIDING_HISTORY_*).
int32_t sliding_history(int tangential);
// The keyword of a tangential model, as pair_coeff takes it.
const char *tangential_name(int tangential);
enum Twist { TWIST_NONE, TWIST_SDS, TWIST_MARSHALL };

// One contact model's coefficients, stored as LAMMPS' pair granular stores them.
struct Coeffs {
  bool set = false;
  int normal = HOOKE;
  double kn = 0.0;         // LAMMPS' normal_coeffs[0] (hertz/material: 4/3 E*)
  double damp = 0.0;       // eta_n (tsuji: from the restitution coefficient)
  double emod = 0.0, poisson = 0.0;
  double coh = 0.0;        // dmt, jkr: the cohesion energy density
  int damping = VISCOELASTIC;
  int tangential = LINEAR_HISTORY;
  double kt = 0.0, xgammat = 0.0, mu_s = 0.0;    // linear_nohistory: kt = 0
  bool rolling = false;
  double kr = 0.0, gr = 0.0, mu_r = 0.0;
  int twist = TWIST_NONE;
  double ktw = 0.0, gtw = 0.0, mu_tw = 0.0;
  bool limit_damping = false;
  double cutoff = -1.0;
  bool operator==(const Coeffs &o) const;
};

// Reports a bad argument: a LAMMPS error with the caller's prefix; never returns.
using Fail = std::function<void(const std::string &)>;

// Parses pair granular's keywords (the supported subset) from arg[iarg], arg[iarg + 1], ...
// into `c`, up to narg or, if `stop` is given, up to the first word for which stop(word) is
// true; returns the index of the first word not parsed. A word that is neither a keyword nor a
// stop word, missing parameters, or a missing normal or tangential model is reported to
// `fail`, naming the keyword (`what` prefixes the messages, e.g. "pair_coeff").
int parse(LAMMPS *lmp, int narg, char **arg, int iarg, Coeffs &c, const std::string &what,
          const Fail &fail, const std::function<bool(const char *)> &stop = nullptr);

// A library model of the preset (RSL_PRESET_*) with coefficients `c` (the sliding dashpot per
// contact unless `damping velocity`, see NormalForce::sliding_damping), energy tracking on if
// `track_energy`; nullptr with `error` set if the library refuses them.
rsl_model *new_model(int32_t preset, const Coeffs &c, bool track_energy, std::string &error);

// JKR (E = 3/4 of the normal coefficient, E*; R the effective radius): the overlap of contact
// radius a is delta(a) = a^2/R - 2 sqrt(pi coh a / E); the contact radius of an overlap is the
// largest root a of delta(a) = delta (the stable branch), by Newton's method from above: delta(a)
// is convex, so from a point right of the root the iterates fall monotonically onto it, and
// the iteration stops when they stop falling (converged to rounding). The start, a =
// max(sqrt(2 R delta), (2 c R)^(2/3)) with c = 2 sqrt(pi coh / E), has a^2/R >= delta + c sqrt(a)
// (each half of a^2/R bounds one term), so it is right of the root. For an overlap below the
// branch's minimum (no root) it returns the minimum's a.
inline double jkr_contact_radius(double estar, double coh, double delta, double reff)
{
  const double c = 2 * sqrt(M_PI * coh / estar);
  double a = fmax(sqrt(2 * reff * fmax(delta, 0.0)), cbrt(2 * c * reff * 2 * c * reff));
  if (a == 0.0) return 0.0;
  for (int k = 0; k < 200; k++) {
    const double sa = sqrt(a);
    const double g = a * a / reff - c * sa - delta;
    const double dg = 2 * a / reff - 0.5 * c / sa;
    if (!(dg > 0.0)) break;
    const double next = a - g / dg;
    if (!(next < a)) break;
    a = next;
  }
  return a;
}
// The pull-off overlap of a pair (negative: the contact persists while the overlap stays above
// it): delta at LAMMPS' pull-off radius a = (9 pi coh R^2 / (4 E))^(1/3).
inline double jkr_pulloff_overlap(double estar, double coh, double reff)
{
  const double a = cbrt(9 * M_PI * coh * reff * reff / (4 * estar));
  return a * a / reff - 2 * sqrt(M_PI * coh * a / estar);
}
// The JKR normal force at contact radius a: F = 4/3 E a^3/R - 4 sqrt(pi coh E a^3) (kn = 4/3 E).
inline double jkr_force(double kn, double coh, double a, double reff)
{
  const double estar = 0.75 * kn;
  return kn * a * a * a / reff - 4 * sqrt(M_PI * coh * estar * a * a * a);
}
// The JKR normal force's potential: the work of F along the JKR curve from the touch (delta =
// 0, a = a0 = (c R)^(2/3)) to contact radius a. With delta'(a) = 2a/R - (c/2) a^(-1/2), the
// integrand F delta'(a) integrates to P(a) = (8/15) E a^5/R^2 - (8/3) sqrt(pi coh E) a^(7/2)/R
// + 2 pi coh a^2; U(a) = P(a) - P(a0).
inline double jkr_potential_at(double estar, double coh, double a, double reff)
{
  const double sa = sqrt(a);
  return 8.0 / 15.0 * estar * a * a * a * a * a / (reff * reff) -
      8.0 / 3.0 * sqrt(M_PI * coh * estar) * a * a * a * sa / reff + 2 * M_PI * coh * a * a;
}
inline double jkr_potential(double estar, double coh, double a, double reff)
{
  const double c = 2 * sqrt(M_PI * coh / estar);
  const double a0 = cbrt(c * reff * c * reff);
  return jkr_potential_at(estar, coh, a, reff) - jkr_potential_at(estar, coh, a0, reff);
}

// The normal force of one contact, as LAMMPS 20220106's granular models compute it, and the
// per-contact sliding coefficients that go with it.
struct NormalForce {
  double force;              // total normal force (compressive positive), dashpot included
  double elastic_force;      // the normal spring's part of `force`
  double damping_force;      // the dashpot's part of `force` before limit_damping: -eta vn
  double elastic;            // energy of the normal spring at this overlap
  double sliding_stiffness;  // k_t (the mindlin family: kt a; linear_nohistory: 0)
  double sliding_damping;    // gamma_t = xgammat times the normal dashpot's prefactor
  bool per_contact_stiffness, per_contact_damping;  // whether the step must pass them
  // Cohesive models (dmt, jkr): the limits use `limit_force` (LAMMPS' Fncrit = |Fne + 2 F_pulloff|,
  // passed with RSL_INPUT_LIMIT_FORCE), which the batch calls cannot take: such contacts are
  // stepped one at a time. The other models' limit force is the preset's own (not passed; 0).
  bool cohesive;
  double limit_force;
  double contact_radius;     // a: sqrt(delta R_eff), JKR's own for jkr
};
// delta: overlap (> 0; for jkr also a neck's negative overlap beyond touching); reff: effective
// radius; meff: effective mass; vn: normal velocity of body 1 relative to body 2 along the
// normal from body 2 to body 1 (negative while approaching).
// The normal dashpot's prefactor eta_n of pair granular 20220106 (damping_normal_prefactor:
// its damping model's factor times the coefficient), for the contact radius a, LAMMPS' knfac
// (the normal stiffness at this overlap) and the effective mass.
inline double damping_prefactor(const Coeffs &c, double a, double knfac, double meff)
{
  double damp_normal;
  switch (c.damping) {
    case VELOCITY: damp_normal = 1; break;
    case MASS_VELOCITY: damp_normal = meff; break;
    case VISCOELASTIC: damp_normal = a * meff; break;
    default: damp_normal = sqrt(meff * knfac); break;
  }
  return c.damp * damp_normal;
}

// The per-contact sliding coefficients of pair granular: the tangential dashpot scales with the
// normal one for every damping model but velocity (with velocity it is the model's constant
// xgammat eta_n, to the bit), the mindlin family's k_t with the contact radius a
// (linear_history's and linear_nohistory's is the model's constant).
inline void set_sliding_coefficients(NormalForce &out, const Coeffs &c, double a,
                                     double damp_normal_prefactor)
{
  out.per_contact_damping = c.damping != VELOCITY;
  out.per_contact_stiffness = is_mindlin(c.tangential);
  out.sliding_damping = c.xgammat * damp_normal_prefactor;
  out.sliding_stiffness = out.per_contact_stiffness ? c.kt * a : c.kt;
}

// dmt and jkr, kept out of line (JKR's contact radius is an iteration) so that the inline
// normal force of the pair style's hot loop stays small.
__attribute__((noinline)) inline NormalForce cohesive_normal_force(const Coeffs &c, double delta,
                                                                   double reff, double meff,
                                                                   double vn)
{
  // The arithmetic of pair granular 20220106, operation for operation (its tests compare bits).
  const bool jkr = c.normal == JKR;
  double knfac = c.kn;
  double Fne;
  double a;
  if (jkr) {
    // JKR's contact radius (delta may be negative: a neck beyond touching).
    a = jkr_contact_radius(0.75 * c.kn, c.coh, delta, reff);
    knfac *= a;
    Fne = jkr_force(c.kn, c.coh, a, reff);
  } else {
    a = sqrt(delta * reff);
    Fne = knfac * delta * a;
    knfac *= a;
  }
  const double hertz_force = Fne;
  // DMT: the pull-off force 4 pi coh R_eff, subtracted as pair granular does.
  const double pulloff = jkr ? 0.0 : 4 * M_PI * c.coh * reff;
  Fne -= pulloff;
  const double damp_normal_prefactor = damping_prefactor(c, a, knfac, meff);
  NormalForce out;
  out.damping_force = -damp_normal_prefactor * vn;
  out.elastic_force = Fne;
  out.force = Fne + out.damping_force;
  if (c.limit_damping && out.force < 0.0) out.force = 0.0;    // (refused for dmt, jkr)
  // DMT: the Hertz spring's energy minus the pull-off force's work, (2/5) k sqrt(R) delta^(5/2)
  // - 4 pi coh R delta (zero at delta = 0, where the contact forms and breaks). JKR: U(a).
  out.elastic = jkr ? jkr_potential(0.75 * c.kn, c.coh, a, reff)
                    : 0.4 * hertz_force * delta - pulloff * delta;
  out.cohesive = true;
  out.contact_radius = a;
  // LAMMPS' Fncrit = |Fne + 2 F_pulloff| (F_pulloff = 4 pi coh R for DMT, 3 pi coh R for JKR).
  out.limit_force = jkr ? fabs(Fne + 2 * (3 * M_PI * c.coh * reff)) : fabs(Fne + 2 * pulloff);
  set_sliding_coefficients(out, c, a, damp_normal_prefactor);
  return out;
}

// Every model; inline for hooke, hertz and hertz/material, which the pair style calls once per
// touching pair in its hot loop (dmt and jkr: cohesive_normal_force).
inline NormalForce normal_force(const Coeffs &c, double delta, double reff, double meff, double vn)
{
  static_assert(JKR > HERTZ_MATERIAL && DMT > HERTZ_MATERIAL, "the cohesive models close the list");
  if (__builtin_expect(c.normal > HERTZ_MATERIAL, 0))
    return cohesive_normal_force(c, delta, reff, meff, vn);
  // The arithmetic of pair granular 20220106, operation for operation (its tests compare bits).
  const double dR = delta * reff;
  double knfac = c.kn;
  double Fne = knfac * delta;
  const double a = sqrt(dR);
  if (c.normal != HOOKE) {
    Fne *= a;
    knfac *= a;
  }
  const double damp_normal_prefactor = damping_prefactor(c, a, knfac, meff);
  NormalForce out;
  out.damping_force = -damp_normal_prefactor * vn;
  out.elastic_force = Fne;
  out.force = Fne + out.damping_force;
  if (c.limit_damping && out.force < 0.0) out.force = 0.0;
  // Hooke: F = k delta, energy k delta^2 / 2; Hertz: F = k sqrt(R) delta^(3/2), energy
  // (2/5) k sqrt(R) delta^(5/2) = (2/5) F delta.
  out.elastic = (c.normal == HOOKE ? 0.5 : 0.4) * Fne * delta;
  out.cohesive = false;
  out.contact_radius = a;
  out.limit_force = 0.0;    // not passed: the preset's own rule, LAMMPS' |Fntot|
  set_sliding_coefficients(out, c, a, damp_normal_prefactor);
  return out;
}

// The energy the normal dashpot dissipated in a step of length dt, for the normal force `nf`
// computed at normal velocity vn (as passed to normal_force): the dashpot force actually
// applied, `force - elastic_force`, times the rate at which the overlap shrinks, -vn, times dt.
// Without limit_damping's clip that is eta vn^2 dt; when the clip holds the total force at
// zero (separating contacts, vn > 0), the applied dashpot force is -elastic_force and the
// dissipation elastic_force vn dt (the energy the spring releases while the clipped force does
// no work). Never negative.
inline double normal_dissipation(const NormalForce &nf, double vn, double dt)
{
  return -(nf.force - nf.elastic_force) * vn * dt;
}

}    // namespace granular
}    // namespace LAMMPS_NS

#endif
