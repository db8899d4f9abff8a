// The granular contact model shared by the pair style and the wall fix: see granular_model.h.
#include "granular_model.h"

#include "lammps.h"
#include "pointers.h"
#include "utils.h"

#include <cmath>
#include <cstdlib>
#include <cstring>

using namespace LAMMPS_NS;
using namespace LAMMPS_NS::granular;

namespace {

// x^n for an integer n >= 0 by binary exponentiation (as LAMMPS' powint evaluates it, so the
// tsuji coefficient has the same bits as pair granular's).
double power(double x, int n)
{
  if (n == 0) return 1.0;
  if (x == 0.0) return 0.0;
  double result = 1.0;
  for (double w = x; n != 0; n >>= 1, w *= w)
    if (n & 1) result *= w;
  return result;
}

// Effective modulus and shear modulus of two identical materials, LAMMPS' mixing rules.
double mix_e(double e1, double e2, double nu1, double nu2)
{
  return 1 / ((1 - nu1 * nu1) / e1 + (1 - nu2 * nu2) / e2);
}
double mix_g(double e1, double e2, double nu1, double nu2)
{
  return 1 / ((2 * (2 - nu1) * (1 + nu1) / e1) + (2 * (2 - nu2) * (1 + nu2) / e2));
}

}    // namespace

int32_t granular::sliding_history(int tangential)
{
  switch (tangential) {
    case MINDLIN_RESCALE: return RSL_SLIDING_HISTORY_DISPLACEMENT_RESCALED;
    case MINDLIN_FORCE: return RSL_SLIDING_HISTORY_FORCE;
    case MINDLIN_RESCALE_FORCE: return RSL_SLIDING_HISTORY_FORCE_RESCALED;
    default: return RSL_SLIDING_HISTORY_DISPLACEMENT;    // linear_*, mindlin
  }
}

const char *granular::tangential_name(int tangential)
{
  switch (tangential) {
    case LINEAR_NOHISTORY: return "linear_nohistory";
    case LINEAR_HISTORY: return "linear_history";
    case MINDLIN: return "mindlin";
    case MINDLIN_RESCALE: return "mindlin_rescale";
    case MINDLIN_FORCE: return "mindlin/force";
    default: return "mindlin_rescale/force";
  }
}

bool Coeffs::operator==(const Coeffs &o) const
{
  return normal == o.normal && kn == o.kn && damp == o.damp && emod == o.emod &&
      poisson == o.poisson && coh == o.coh && damping == o.damping && tangential == o.tangential && kt == o.kt &&
      xgammat == o.xgammat && mu_s == o.mu_s && rolling == o.rolling && kr == o.kr &&
      gr == o.gr && mu_r == o.mu_r && twist == o.twist && ktw == o.ktw && gtw == o.gtw &&
      mu_tw == o.mu_tw && limit_damping == o.limit_damping && cutoff == o.cutoff;
}

int granular::parse(LAMMPS *lmp, int narg, char **arg, int iarg, Coeffs &c,
                    const std::string &what, const Fail &fail,
                    const std::function<bool(const char *)> &stop)
{
  c = Coeffs();
  bool has_normal = false, has_tangential = false, kt_null = false;
  auto need = [&](int k, int n, const char *kw) {
    if (k + n >= narg) fail(what + ": not enough parameters for '" + kw + "'");
  };
  auto num = [&](int k) { return utils::numeric(FLERR, arg[k], false, lmp); };
  while (iarg < narg) {
    const char *kw = arg[iarg];
    if (stop && stop(kw)) break;
    if (strcmp(kw, "hooke") == 0 || strcmp(kw, "hertz") == 0) {
      need(iarg, 2, kw);
      c.normal = strcmp(kw, "hooke") == 0 ? HOOKE : HERTZ;
      c.kn = num(iarg + 1);
      c.damp = num(iarg + 2);
      has_normal = true;
      iarg += 3;
    } else if (strcmp(kw, "hertz/material") == 0) {
      need(iarg, 3, kw);
      c.normal = HERTZ_MATERIAL;
      c.emod = num(iarg + 1);
      c.damp = num(iarg + 2);
      c.poisson = num(iarg + 3);
      has_normal = true;
      iarg += 4;
    } else if (strcmp(kw, "dmt") == 0 || strcmp(kw, "jkr") == 0) {
      // E eta_n nu coh (a keyword where a number should be: coh, or more, left out)
      need(iarg, 4, kw);
      for (int k = 1; k <= 4; k++) {
        char *end = nullptr;
        strtod(arg[iarg + k], &end);
        if (end == arg[iarg + k] || *end != '\0')
          fail(what + ": '" + kw + "' needs E, eta_n, nu and coh (got '" + arg[iarg + k] +
               "' for " + (k == 1 ? "E" : k == 2 ? "eta_n" : k == 3 ? "nu" : "coh") + ")");
      }
      c.normal = strcmp(kw, "dmt") == 0 ? DMT : JKR;
      c.emod = num(iarg + 1);
      c.damp = num(iarg + 2);
      c.poisson = num(iarg + 3);
      c.coh = num(iarg + 4);
      has_normal = true;
      iarg += 5;
    } else if (strcmp(kw, "damping") == 0) {
      need(iarg, 1, kw);
      const char *d = arg[iarg + 1];
      if (strcmp(d, "velocity") == 0) c.damping = VELOCITY;
      else if (strcmp(d, "mass_velocity") == 0) c.damping = MASS_VELOCITY;
      else if (strcmp(d, "viscoelastic") == 0) c.damping = VISCOELASTIC;
      else if (strcmp(d, "tsuji") == 0) c.damping = TSUJI;
      else fail(what + ": damping model '" + d + "' is not supported");
      iarg += 2;
    } else if (strcmp(kw, "tangential") == 0) {
      need(iarg, 1, kw);
      const char *t = arg[iarg + 1];
      static const int models[] = {LINEAR_NOHISTORY, LINEAR_HISTORY, MINDLIN, MINDLIN_RESCALE,
                                   MINDLIN_FORCE, MINDLIN_RESCALE_FORCE};
      bool known = false;
      for (int m : models)
        if (strcmp(t, tangential_name(m)) == 0) {
          c.tangential = m;
          known = true;
        }
      if (!known)
        fail(what + ": tangential model '" + t +
             "' is not supported (linear_nohistory, linear_history, mindlin, mindlin_rescale, "
             "mindlin/force, mindlin_rescale/force)");
      if (c.tangential == LINEAR_NOHISTORY) {
        // gammat mu_s: no spring (stock stores k_t = 0).
        need(iarg, 3, t);
        c.kt = 0.0;
        c.xgammat = num(iarg + 2);
        c.mu_s = num(iarg + 3);
        kt_null = false;
        iarg += 4;
      } else {
        // kt|NULL xgammat mu_s (NULL: the mindlin family with hertz/material only, below).
        need(iarg, 4, t);
        kt_null = is_mindlin(c.tangential) && strcmp(arg[iarg + 2], "NULL") == 0;
        if (!kt_null) c.kt = num(iarg + 2);
        c.xgammat = num(iarg + 3);
        c.mu_s = num(iarg + 4);
        iarg += 5;
      }
      has_tangential = true;
    } else if (strcmp(kw, "rolling") == 0) {
      need(iarg, 1, kw);
      if (strcmp(arg[iarg + 1], "none") == 0) {
        c.rolling = false;
        iarg += 2;
      } else if (strcmp(arg[iarg + 1], "sds") == 0) {
        need(iarg, 4, "rolling sds");
        c.rolling = true;
        c.kr = num(iarg + 2);
        c.gr = num(iarg + 3);
        c.mu_r = num(iarg + 4);
        iarg += 5;
      } else
        fail(what + ": rolling model '" + arg[iarg + 1] + "' is not supported");
    } else if (strcmp(kw, "twisting") == 0) {
      need(iarg, 1, kw);
      if (strcmp(arg[iarg + 1], "none") == 0) {
        c.twist = TWIST_NONE;
        iarg += 2;
      } else if (strcmp(arg[iarg + 1], "marshall") == 0) {
        c.twist = TWIST_MARSHALL;
        iarg += 2;
      } else if (strcmp(arg[iarg + 1], "sds") == 0) {
        need(iarg, 4, "twisting sds");
        c.twist = TWIST_SDS;
        c.ktw = num(iarg + 2);
        c.gtw = num(iarg + 3);
        c.mu_tw = num(iarg + 4);
        iarg += 5;
      } else
        fail(what + ": twisting model '" + arg[iarg + 1] + "' is not supported");
    } else if (strcmp(kw, "cutoff") == 0) {
      need(iarg, 1, kw);
      c.cutoff = num(iarg + 1);
      iarg += 2;
    } else if (strcmp(kw, "limit_damping") == 0) {
      c.limit_damping = true;
      iarg += 1;
    } else {
      fail(what + ": keyword '" + kw +
           "' is not supported (normal hooke, hertz, hertz/material, dmt, jkr; damping velocity, "
           "mass_velocity, viscoelastic, tsuji; tangential linear_nohistory, linear_history, "
           "mindlin, mindlin_rescale, mindlin/force, mindlin_rescale/force; rolling sds; "
           "twisting sds, marshall; cutoff; limit_damping)");
    }
  }
  if (!has_normal || !has_tangential) fail(what + ": a normal model and a tangential model are required");
  if (kt_null && (c.normal == HOOKE || c.normal == HERTZ))
    fail(what + ": tangential " + tangential_name(c.tangential) +
         " NULL (the stiffness from the material) needs the hertz/material normal model "
         "(or dmt, jkr)");
  if (c.limit_damping && (c.normal == DMT || c.normal == JKR))
    fail(what + ": limit_damping cannot be used with the " + (c.normal == DMT ? "dmt" : "jkr") +
         " normal model (as pair granular)");
  // As pair granular stores them.
  if (c.damping == TSUJI) {
    double cor = c.damp;
    c.damp = 1.2728 - 4.2783 * cor + 11.087 * cor * cor - 22.348 * (cor * cor * cor) +
        27.467 * power(cor, 4) - 18.022 * power(cor, 5) + 4.8218 * power(cor, 6);
  }
  if (c.normal == HERTZ_MATERIAL || c.normal == DMT || c.normal == JKR) c.kn = 4.0 / 3.0 * mix_e(c.emod, c.emod, c.poisson, c.poisson);
  if (kt_null) c.kt = 8 * mix_g(c.emod, c.emod, c.poisson, c.poisson);
  c.set = true;
  return iarg;
}

rsl_model *granular::new_model(int32_t preset, const Coeffs &c, bool track_energy, std::string &error)
{
  rsl_model *m = nullptr;
  int32_t st = rsl_model_new(preset, &m);
  // The sliding dashpot is per contact (xgammat times the normal damping prefactor),
  // except with `damping velocity`, where it is the constant xgammat eta_n.
  double gamma_t = c.damping == VELOCITY ? c.xgammat * c.damp : 0.0;
  // linear_nohistory: the linear law without a spring (k_t = 0: the dashpot's force, clipped
  // at the friction limit); the mindlin family's k_t = kt a comes per contact. What the spring
  // stores (a displacement or its elastic force) and whether it is scaled down with k_t on
  // unloading: RSL_SLIDING_HISTORY_*.
  if (st == RSL_OK) st = rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, c.kt, gamma_t, c.mu_s);
  if (st == RSL_OK) st = rsl_model_set_sliding_history(m, sliding_history(c.tangential));
  if (st == RSL_OK && c.rolling) {
    rsl_rolling_params p;
    st = rsl_model_get_rolling(m, &p);
    p.law = RSL_ROLLING_EPSD;
    p.form = RSL_FORM_LENGTH;
    p.stiffness_rule = RSL_STIFFNESS_GIVEN;
    p.damping_rule = RSL_DAMPING_GIVEN;
    p.damping_mode = RSL_DAMPING_ALWAYS;
    p.stiffness = c.kr;
    p.damping = c.gr;
    p.friction = c.mu_r;
    if (st == RSL_OK) st = rsl_model_set_rolling(m, &p);
  }
  if (st == RSL_OK && c.twist == TWIST_SDS)
    st = rsl_model_set_twisting(m, RSL_TWISTING_SDS, c.ktw, c.gtw, c.mu_tw);
  if (st == RSL_OK && c.twist == TWIST_MARSHALL)
    st = rsl_model_set_twisting(m, RSL_TWISTING_MARSHALL, 0.0, 0.0, 0.0);
  if (st == RSL_OK && track_energy) st = rsl_model_set_energy_tracking(m, 1);
  if (st != RSL_OK) {
    rsl_model_free(m);
    error = std::string(rsl_status_str(st)) + " (" + rsl_last_error_message() + ")";
    return nullptr;
  }
  return m;
}
