// fix wall/gran/rollslide: see fix_wall_gran_rollslide.h and docs/lammps.md ("The wall fix").
//
// Conventions: the atom is the library's body 1 and the wall its body 2 (rsl_wall: a point of
// the wall surface, the wall's outward normal towards the atom, the velocity of the wall's
// material point there, the wall's angular velocity). LAMMPS' wall normal n (from the wall to
// the atom) is the library's -n; the library returns the whole force on the atom (normal +
// sliding) and the torque on it about its centre.
//
// What follows stock LAMMPS 20220106's fix wall/gran granular (src/GRANULAR/fix_wall_gran.cpp,
// read, not copied): the distance to the nearer wall of a plane pair, the cylinder's effective
// radius R r_w / (R + r_w) with r_w = -2 r_c inside, +2 r_c outside (the normal force and
// Marshall's contact radius use it), the wall's velocity under wiggle and shear, m_eff = the
// atom's mass, the wall coefficients of hertz/material and of `mindlin NULL` (any model of the
// mindlin family) as stock computes them (not pair granular's), no history increment in the
// setup pass, one history per atom.
#include "fix_wall_gran_rollslide.h"

#include "compute_rollslide_energy.h"

#include "atom.h"
#include "comm.h"
#include "compute.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "modify.h"
#include "update.h"
#include "utils.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

static_assert(sizeof(rsl_contact_state) == 13 * sizeof(double) + 2 * sizeof(uint32_t),
              "rsl_contact_state: 13 doubles and two 32-bit integers");

namespace {

constexpr double PI = 3.14159265358979323846;

bool is_wall_style(const char *w)
{
  return strcmp(w, "xplane") == 0 || strcmp(w, "yplane") == 0 || strcmp(w, "zplane") == 0 ||
      strcmp(w, "zcylinder") == 0;
}

// Words that end the granular keywords: the supported wall styles, stock's other one (region)
// and anything else named like a wall style (xcylinder, ...), which are then refused by name.
bool ends_keywords(const char *w)
{
  auto ends_with = [w](const char *tail) {
    const size_t n = strlen(w), k = strlen(tail);
    return n >= k && strcmp(w + n - k, tail) == 0;
  };
  return is_wall_style(w) || strcmp(w, "region") == 0 || ends_with("plane") ||
      ends_with("cylinder");
}

}    // namespace

FixWallGranRollslide::FixWallGranRollslide(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  const char *usage =
      "expected `fix ID group wall/gran/rollslide granular <pair granular keywords> "
      "xplane|yplane|zplane lo hi | zcylinder radius [wiggle dim A period | shear dim v] "
      "[preset objective|lammps]`";
  if (narg < 4) fail(usage);
  if (!atom->sphere_flag) fail("needs atom_style sphere");

  // The interaction style: granular only.
  if (strcmp(arg[3], "granular") != 0) {
    if (strcmp(arg[3], "hooke") == 0 || strcmp(arg[3], "hooke/history") == 0 ||
        strcmp(arg[3], "hertz/history") == 0)
      fail(std::string("interaction style '") + arg[3] +
           "' is not supported (only granular, with pair granular's keywords)");
    fail(std::string("unknown interaction style '") + arg[3] + "' (expected granular); " + usage);
  }

  // The granular keywords, up to the wall style.
  const int first = 4;
  int iarg = granular::parse(
      lmp, narg, arg, first, coeffs, "granular", [this](const std::string &m) { fail(m); },
      ends_keywords);
  const int last = iarg;    // arg[first .. last) are the granular keywords

  // The keywords parse() takes that a wall has no use for.
  for (int k = first; k < last; k++)
    if (strcmp(arg[k], "cutoff") == 0)
      fail("keyword 'cutoff' is not supported by the wall (it has no neighbour list)");

  // Stock fix wall/gran's own coefficients where they are not pair granular's: the normal
  // stiffness of hertz/material (E/(2(1-nu)) 4/3, with its 16-digit 4/3), the `mindlin NULL`
  // shear stiffness (E/4 (2-nu)(1+nu)), and tsuji's damping from the restitution coefficient
  // (with pow, as stock evaluates it). Read from the keywords parse() accepted (the last of
  // each, as parse keeps the last).
  {
    const double stock_four_thirds = 1.333333333333333;
    int normal_at = -1, tangential_at = -1;
    for (int k = first; k < last; k++) {
      if (strcmp(arg[k], "hooke") == 0 || strcmp(arg[k], "hertz") == 0 ||
          strcmp(arg[k], "hertz/material") == 0 || strcmp(arg[k], "dmt") == 0 ||
          strcmp(arg[k], "jkr") == 0)
        normal_at = k;
      if (strcmp(arg[k], "tangential") == 0) tangential_at = k;
    }
    if (coeffs.normal == granular::HERTZ_MATERIAL || coeffs.normal == granular::DMT ||
        coeffs.normal == granular::JKR)
      coeffs.kn = coeffs.emod / (2 * (1 - coeffs.poisson)) * stock_four_thirds;
    // (The last tangential keyword is the model parse() kept: any of the mindlin family takes
    // NULL, and parse() read its three parameters.)
    if (tangential_at >= 0 && granular::is_mindlin(coeffs.tangential) &&
        strcmp(arg[tangential_at + 2], "NULL") == 0)
      coeffs.kt = coeffs.emod / 4 * (2 - coeffs.poisson) * (1 + coeffs.poisson);
    if (coeffs.damping == granular::TSUJI && normal_at >= 0) {
      const double cor = utils::numeric(FLERR, arg[normal_at + 2], false, lmp);
      coeffs.damp = 1.2728 - 4.2783 * cor + 11.087 * pow(cor, 2) - 22.348 * pow(cor, 3) +
          27.467 * pow(cor, 4) - 18.022 * pow(cor, 5) + 4.8218 * pow(cor, 6);
    }
  }

  // The wall style.
  if (iarg >= narg)
    fail("a wall style (xplane, yplane, zplane or zcylinder) must follow the granular keywords");
  const char *ws = arg[iarg];
  if (!is_wall_style(ws))
    fail(std::string("wall style '") + ws +
         "' is not supported (xplane, yplane, zplane, zcylinder)");
  if (strcmp(ws, "zcylinder") == 0) {
    if (iarg + 1 >= narg) fail("zcylinder needs its radius");
    wallstyle = ZCYLINDER;
    cylradius = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
    if (!(cylradius > 0.0))
      fail(std::string("zcylinder radius must be > 0 (got ") + arg[iarg + 1] + ")");
    iarg += 2;
  } else {
    wallstyle = ws[0] == 'x' ? XPLANE : ws[0] == 'y' ? YPLANE : ZPLANE;
    if (iarg + 2 >= narg) fail(std::string(ws) + " needs lo and hi (a position, EDGE or NULL)");
    auto position = [&](const char *word, bool low, bool &has, double &at) {
      has = strcmp(word, "NULL") != 0;
      if (!has) return;
      if (strcmp(word, "EDGE") == 0)
        at = low ? domain->boxlo[wallstyle] : domain->boxhi[wallstyle];
      else
        at = utils::numeric(FLERR, word, false, lmp);
    };
    position(arg[iarg + 1], true, has_lo, lo);
    position(arg[iarg + 2], false, has_hi, hi);
    if (!has_lo && !has_hi) fail(std::string(ws) + ": lo and hi are both NULL (no wall)");
    if (has_lo && has_hi && !(lo < hi))
      fail(std::string(ws) + ": lo must be below hi");
    iarg += 3;
  }

  // Optional keywords.
  auto dimension = [&](const char *kw, const char *d) {
    if (strcmp(d, "x") == 0) return 0;
    if (strcmp(d, "y") == 0) return 1;
    if (strcmp(d, "z") == 0) return 2;
    fail(std::string(kw) + ": dimension must be x, y or z (got '" + d + "')");
  };
  while (iarg < narg) {
    const char *kw = arg[iarg];
    if (strcmp(kw, "wiggle") == 0) {
      if (iarg + 3 >= narg) fail("wiggle needs dim, amplitude and period");
      axis = dimension(kw, arg[iarg + 1]);
      amplitude = utils::numeric(FLERR, arg[iarg + 2], false, lmp);
      period = utils::numeric(FLERR, arg[iarg + 3], false, lmp);
      if (!(period > 0.0))
        fail(std::string("wiggle period must be > 0 (got ") + arg[iarg + 3] + ")");
      wiggle = true;
      iarg += 4;
    } else if (strcmp(kw, "shear") == 0) {
      if (iarg + 2 >= narg) fail("shear needs dim and velocity");
      axis = dimension(kw, arg[iarg + 1]);
      vshear = utils::numeric(FLERR, arg[iarg + 2], false, lmp);
      wshear = true;
      iarg += 3;
    } else if (strcmp(kw, "preset") == 0) {
      if (iarg + 1 >= narg) fail("preset needs objective or lammps");
      if (strcmp(arg[iarg + 1], "objective") == 0) preset = RSL_PRESET_OBJECTIVE;
      else if (strcmp(arg[iarg + 1], "lammps") == 0) preset = RSL_PRESET_LAMMPS_2021;
      else
        fail(std::string("unknown preset '") + arg[iarg + 1] + "' (expected objective or lammps)");
      iarg += 2;
    } else if (strcmp(kw, "contacts") == 0) {
      fail("keyword 'contacts' is not supported");
    } else {
      fail(std::string("unknown keyword '") + kw + "' (expected wiggle, shear or preset)");
    }
  }

  // Stock's checks.
  if (wallstyle == XPLANE && domain->xperiodic) fail("xplane wall in a periodic dimension");
  if (wallstyle == YPLANE && domain->yperiodic) fail("yplane wall in a periodic dimension");
  if (wallstyle == ZPLANE && domain->zperiodic) fail("zplane wall in a periodic dimension");
  if (wallstyle == ZCYLINDER && (domain->xperiodic || domain->yperiodic))
    fail("zcylinder wall with x or y periodic");
  if (wiggle && wshear) fail("wiggle and shear cannot be used together");
  if (wiggle && wallstyle == ZCYLINDER && axis != 2) fail("a zcylinder wall wiggles along z only");
  if (wshear && wallstyle != ZCYLINDER && axis == wallstyle)
    fail("shear must be along the wall (tangential to the plane)");
  if (wiggle) omega = 2.0 * PI / period;

  // The model now, so that coefficients the library refuses stop the input here.
  make_model(false);

  restart_global = 1;    // the wiggle's time origin
  restart_peratom = 1;
  create_attribute = 1;
  virial_global_flag = virial_peratom_flag = 1;    // with fix_modify virial yes (off by default)
  maxexchange = ATOM_DOUBLES;
  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);
  for (int i = 0; i < atom->nlocal; i++) set_arrays(i);

  time_origin = update->ntimestep;
}

FixWallGranRollslide::~FixWallGranRollslide()
{
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
  rsl_model_free(model);
}

void FixWallGranRollslide::fail(const std::string &message)
{
  error->all(FLERR, std::string("fix wall/gran/rollslide: ") + message);
}

std::string FixWallGranRollslide::wall_name(int wall_side) const
{
  if (wallstyle == ZCYLINDER) return wall_side == LO ? "zcylinder inside" : "zcylinder outside";
  const char *names[3] = {"xplane", "yplane", "zplane"};
  return std::string(names[wallstyle]) + (wall_side == LO ? " lo" : " hi");
}

void FixWallGranRollslide::library_error(const char *call, int32_t status, tagint atom_id,
                                         int wall_side)
{
  // error->one: the failing contact is on this rank only.
  error->one(FLERR, std::string("fix ") + id + " wall/gran/rollslide: " + call +
                        " failed for atom " +
                        std::to_string(atom_id) + " and the wall " + wall_name(wall_side) + ": " +
                        rsl_status_str(status) + " (" + rsl_last_error_message() + ")");
}

void FixWallGranRollslide::make_model(bool track_energy)
{
  std::string message;
  rsl_model *m = granular::new_model(preset, coeffs, track_energy, message);
  if (m == nullptr) fail("the library refused the coefficients: " + message);
  if (preset == RSL_PRESET_LAMMPS_2021) {
    // Stock fix wall/gran's arm: the sliding force acts at the full radius R from the centre
    // (pair granular's, which the preset reproduces, is R - delta/2), and the sliding velocity
    // takes R (w x n): the library's branch rule RSL_BRANCH_RADII for this wall (the preset's
    // rolling radius, R for a flat wall, unchanged).
    const int32_t st = rsl_model_set_geometry(m, RSL_BRANCH_RADII, RSL_ROLLING_RADIUS_EFFECTIVE);
    if (st != RSL_OK) {
      rsl_model_free(m);
      fail(std::string("the library refused the wall's branch rule: ") + rsl_status_str(st));
    }
  }
  rsl_model_free(model);
  model = m;
  model_tracks_energy = track_energy;
}

int FixWallGranRollslide::setmask()
{
  return POST_FORCE;
}

void FixWallGranRollslide::init()
{
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    fail("needs atom_style sphere (radius, rmass, omega, torque)");
  if (utils::strmatch(update->integrate_style, "^respa")) fail("run_style respa is not supported");
  for (int i = 0; i < modify->nfix; i++)
    if (modify->fix[i]->rigid_flag)
      fail(std::string("rigid bodies (fix ") + modify->fix[i]->style + ") are not supported");

  // The energy compute, if there is one: then the library reports each step's energy terms.
  energy = nullptr;
  for (int i = 0; i < modify->ncompute; i++)
    if (strcmp(modify->compute[i]->style, ComputeRollslideEnergy::STYLE) == 0) {
      energy = static_cast<ComputeRollslideEnergy *>(modify->compute[i]);
      break;
    }
  if ((energy != nullptr) != model_tracks_energy) make_model(energy != nullptr);
}

void FixWallGranRollslide::setup(int vflag)
{
  post_force(vflag);
}

void FixWallGranRollslide::post_force(int vflag)
{
  v_init(vflag);
  const bool setup_pass = update->setupflag != 0;
  const double dt = update->dt;
  if (energy) energy->begin_step();

  // The wall's position and velocity this step (stock's wiggle and shear).
  double wlo = lo, whi = hi;
  double vwall[3] = {0.0, 0.0, 0.0};
  bool spinning = false;    // a zcylinder turning about z (shear x or y)
  if (wiggle) {
    const double phase = omega * (double) (update->ntimestep - time_origin) * dt;
    if (wallstyle == axis) {
      wlo = lo + amplitude - amplitude * cos(phase);
      whi = hi + amplitude - amplitude * cos(phase);
    }
    vwall[axis] = amplitude * omega * sin(phase);
  } else if (wshear) {
    if (wallstyle == ZCYLINDER && axis != 2)
      spinning = true;
    else
      vwall[axis] = vshear;
  }

  double **x = atom->x;
  double **v = atom->v;
  double **f = atom->f;
  double **omega_atom = atom->omega;
  double **torque = atom->torque;
  double *radius = atom->radius;
  double *rmass = atom->rmass;
  int *mask = atom->mask;
  tagint *tag = atom->tag;
  const int nlocal = atom->nlocal;
  const bool batched = !setup_pass && !evflag && wallstyle != ZCYLINDER;
  chunk.clear();

  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    const double rad = radius[i];

    // d: from the wall's nearest point to the atom's centre; rwall: the wall's radius of
    // curvature as stock uses it (0: flat).
    // rsq = |d|^2 from the components just computed (rather than read back from d, which was
    // written by a run-time index: the load of the whole array then waited on that store, a
    // fifth of the fix's samples on in.heap, for every atom of every step).
    double d[3] = {0.0, 0.0, 0.0};
    double rwall = 0.0, delxy = 0.0, rsq = 0.0;
    int wall_side = NO_WALL;
    if (wallstyle == ZCYLINDER) {
      delxy = sqrt(x[i][0] * x[i][0] + x[i][1] * x[i][1]);
      const double delr = cylradius - delxy;
      if (delr <= rad) {
        const double d0 = -delr / delxy * x[i][0], d1 = -delr / delxy * x[i][1];
        d[0] = d0;
        d[1] = d1;
        rsq = d0 * d0 + d1 * d1;
        const bool inside = delxy < cylradius;
        rwall = inside ? -2 * cylradius : 2 * cylradius;
        wall_side = inside ? LO : HI;
      }
    } else {
      const int k = wallstyle;
      const double del1 = x[i][k] - wlo, del2 = whi - x[i][k];
      const bool low = has_lo && (!has_hi || del1 < del2);
      const double dk = low ? del1 : -del2;
      d[k] = dk;
      rsq = dk * dk;
      wall_side = low ? LO : HI;
    }
    // JKR: a contact that touched (side[i] set: stock's per-atom touch flag) holds until the
    // atom's centre is farther than rad + stock's pull-off distance, which stock's wall
    // computes from the atom's radius as a = (9 pi coh R / (4 E))^(1/3) (R, not pair granular's
    // R^2; its sign varies: negative, a contact forms only once the overlap exceeds it) and
    // delta = a^2/R - 2 sqrt(pi coh a / E). Stock's cylinder finds no contact beyond touching
    // (it measures no distance there), so there a positive one is not used.
    double reach = rad;
    if (coeffs.normal == granular::JKR) {
      const double estar = 0.75 * coeffs.kn;
      const double a = cbrt(9 * PI * coeffs.coh * rad / (4 * estar));
      const double pulloff = a * a / rad - 2 * sqrt(PI * coeffs.coh * a / estar);
      reach = rad + (wallstyle == ZCYLINDER ? fmin(pulloff, 0.0) : pulloff);
    }
    if (wall_side == NO_WALL || rsq > reach * reach ||
        (side[i] == NO_WALL && rsq > rad * rad)) {
      // Not touching: the contact (if any) ends and its history is dropped, as stock does.
      if (side[i] != NO_WALL) end_contact(i);
      continue;
    }
    // A contact with the other wall of the pair (only in a box thinner than the particle) does
    // not inherit this wall's springs.
    if (side[i] != wall_side) {
      if (side[i] != NO_WALL) end_contact(i);
      side[i] = wall_side;
    }

    // The wall's material velocity at the contact (a turning cylinder: its surface's).
    double vw[3] = {vwall[0], vwall[1], vwall[2]};
    double spin[3] = {0.0, 0.0, 0.0};
    if (spinning) {
      vw[0] = vshear * x[i][1] / delxy;
      vw[1] = -vshear * x[i][0] / delxy;
      // The objective preset gives the wall its angular velocity (clockwise about z for
      // vshear > 0, surface speed vshear); stock, and so the lammps preset, ignores it.
      if (preset != RSL_PRESET_LAMMPS_2021) spin[2] = -vshear / cylradius;
    }

    // The normal force, as stock fix wall/gran granular computes it.
    const double r = sqrt(rsq);
    const double rinv = 1.0 / r;
    const double nx = d[0] * rinv, ny = d[1] * rinv, nz = d[2] * rinv;
    const double vnnr = (v[i][0] - vw[0]) * nx + (v[i][1] - vw[1]) * ny + (v[i][2] - vw[2]) * nz;
    const double reff = rwall == 0.0 ? rad : rad * rwall / (rad + rwall);
    const double delta = rad - r;
    const double meff = rmass[i];
    const granular::NormalForce nf = granular::normal_force(coeffs, delta, reff, meff, vnnr);

    rsl_sphere s;
    s.position = {x[i][0], x[i][1], x[i][2]};
    s.velocity = {v[i][0], v[i][1], v[i][2]};
    s.angular_velocity = {omega_atom[i][0], omega_atom[i][1], omega_atom[i][2]};
    s.radius = rad;
    rsl_wall w;
    w.point = {x[i][0] - d[0], x[i][1] - d[1], x[i][2] - d[2]};
    w.normal = {nx, ny, nz};
    w.velocity = {vw[0], vw[1], vw[2]};
    w.angular_velocity = {spin[0], spin[1], spin[2]};

    // The steps that tally the virial, the setup pass and the cylinder go one contact at a
    // time; the others are gathered into chunks, each stepped by one batch call.
    // (Cohesive contacts too: their limit force is per contact, which the batch call lacks.)
    if (batched && !nf.cohesive) {
      if (chunk.size() == CHUNK || (chunk.size() > 0 && !chunk.same_coefficients(nf)))
        flush_chunk(dt);
      chunk.add(i, s, w, nf, energy ? granular::normal_dissipation(nf, vnnr, dt) : 0.0);
      continue;
    }

    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.normal_force = nf.force;
    in.dt = dt;
    // Marshall's contact radius with stock's effective radius (the cylinder's curvature
    // included; the library's own would be the flat wall's sqrt(delta R)), JKR's a for jkr.
    in.contact_radius = nf.contact_radius;    // sqrt(delta reff); JKR's a for jkr
    if (setup_pass) in.flags |= RSL_INPUT_SETUP;
    if (nf.cohesive) {
      in.flags |= RSL_INPUT_LIMIT_FORCE;
      in.limit_force = nf.limit_force;
    }
    if (nf.per_contact_damping) {
      in.flags |= RSL_INPUT_SLIDING_DAMPING;
      in.sliding_damping = nf.sliding_damping;
    }
    if (nf.per_contact_stiffness) {
      in.flags |= RSL_INPUT_SLIDING_STIFFNESS;
      in.sliding_stiffness = nf.sliding_stiffness;
    }
    if (preset == RSL_PRESET_LAMMPS_2021 && coeffs.rolling && rwall != 0.0) {
      // Stock's rolling on the cylinder uses its curved R_eff = s R as the rolling radius
      // (rate s R (w x n), moment s R n x F_r); the library's flat wall has R. The same spring
      // in the variable xi / s, with k_r and gamma_r times s^2 and mu_r times s, is stock's
      // law to rounding (s is constant for a given atom and wall).
      const double scale = reff / rad;
      in.flags |=
          RSL_INPUT_ROLLING_STIFFNESS | RSL_INPUT_ROLLING_DAMPING | RSL_INPUT_ROLLING_FRICTION;
      in.rolling_stiffness = scale * scale * coeffs.kr;
      in.rolling_damping = scale * scale * coeffs.gr;
      in.rolling_friction = scale * coeffs.mu_r;
    }
    rsl_contact_loads out;
    const int32_t st = rsl_contact_step_wall(model, &s, &w, &in, &history[i], &out);
    if (st != RSL_OK)
      library_error("rsl_contact_step_wall", st, atom->tag_enable ? tag[i] : (tagint) i,
                    wall_side);

    f[i][0] += out.force1.x;
    f[i][1] += out.force1.y;
    f[i][2] += out.force1.z;
    torque[i][0] += out.torque1.x;
    torque[i][1] += out.torque1.y;
    torque[i][2] += out.torque1.z;

    if (evflag) {
      double vir[6] = {out.force1.x * d[0], out.force1.y * d[1], out.force1.z * d[2],
                       out.force1.x * d[1], out.force1.x * d[2], out.force1.y * d[2]};
      v_tally(i, vir);
    }

    if (energy) {
      // As the pair style tallies (see its "Energy"): the normal dashpot's dissipation (the
      // dashpot force actually applied, limit_damping's clip included, times the overlap rate,
      // times dt), the library's split of the step, the normal spring's energy.
      double normal_dissipated = granular::normal_dissipation(nf, vnnr, dt);
      rsl_contact_energy e = out.energy;
      if (setup_pass) {
        // A run's setup pass is no time step: no dashpot dissipates. The lammps preset's setup
        // pass writes the history (LAMMPS' clip rules do), so its slider and transport terms
        // stay; the objective preset's writes nothing, so the springs keep the clip's energy.
        normal_dissipated = 0.0;
        e.dashpot_sliding = e.dashpot_rolling = e.dashpot_twisting = 0.0;
        if (preset != RSL_PRESET_LAMMPS_2021) {
          e.elastic_sliding += e.slider_sliding;
          e.elastic_rolling += e.slider_rolling;
          e.elastic_twisting += e.slider_twisting;
          e.slider_sliding = e.slider_rolling = e.slider_twisting = e.transport = 0.0;
          e.stiffness_change = 0.0;
        }
      }
      energy->tally(i, 1.0, true, e, normal_dissipated, nf.elastic);
      spring_energy[4 * i] = e.elastic_sliding;
      spring_energy[4 * i + 1] = e.elastic_rolling;
      spring_energy[4 * i + 2] = e.elastic_twisting;
      spring_energy[4 * i + 3] = nf.elastic;
    }
  }
  if (chunk.size() > 0) flush_chunk(dt);
}

// A chunk's contacts: each atom's sphere, wall, normal force and sliding coefficients, its
// history's index (the atom's), and for the energy compute the normal dashpot's dissipation
// and the normal spring's energy.
void FixWallGranRollslide::Chunk::clear()
{
  atoms.clear();
  spheres.clear();
  walls.clear();
  normal_force.clear();
  sliding_stiffness.clear();
  sliding_damping.clear();
  state_index.clear();
  normal_dissipated.clear();
  normal_elastic.clear();
}

bool FixWallGranRollslide::Chunk::same_coefficients(const granular::NormalForce &nf) const
{
  return nf.per_contact_stiffness == per_contact_stiffness &&
      nf.per_contact_damping == per_contact_damping;
}

void FixWallGranRollslide::Chunk::add(int i, const rsl_sphere &s, const rsl_wall &w,
                                      const granular::NormalForce &nf, double dissipated)
{
  if (atoms.empty()) {
    per_contact_stiffness = nf.per_contact_stiffness;
    per_contact_damping = nf.per_contact_damping;
  }
  atoms.push_back(i);
  spheres.push_back(s);
  walls.push_back(w);
  normal_force.push_back(nf.force);
  sliding_stiffness.push_back(nf.sliding_stiffness);
  sliding_damping.push_back(nf.sliding_damping);
  state_index.push_back((size_t) i);
  normal_dissipated.push_back(dissipated);
  normal_elastic.push_back(nf.elastic);
}

// Steps the chunk in one rsl_batch_step_walls call (each contact its own sphere record, its
// loads accumulated into the chunk's zeroed buffers) and adds the loads to the atoms, in the
// atoms' order, as the per-contact step does.
void FixWallGranRollslide::flush_chunk(double dt)
{
  const size_t n = chunk.size();
  if (sphere_of_contact.size() < n) {
    const size_t first = sphere_of_contact.size();
    sphere_of_contact.resize(n);
    for (size_t c = first; c < n; c++) sphere_of_contact[c] = (uint32_t) c;
  }
  const rsl_vec3 zero = {0.0, 0.0, 0.0};
  chunk_force.assign(n, zero);
  chunk_torque.assign(n, zero);
  rsl_batch_contact_params params;
  memset(&params, 0, sizeof params);
  if (chunk.per_contact_stiffness) params.sliding_stiffness = chunk.sliding_stiffness.data();
  if (chunk.per_contact_damping) params.sliding_damping = chunk.sliding_damping.data();
  if (energy) {
    chunk_energy.resize(n);
    params.energy = chunk_energy.data();
  }
  rsl_batch_report report;
  const int32_t st = rsl_batch_step_walls(
      model, chunk.spheres.data(), n, sphere_of_contact.data(), chunk.walls.data(), n,
      chunk.normal_force.data(), nullptr, &params, dt, nullptr, history.data(), history.size(),
      chunk.state_index.data(), chunk_force.data(), chunk_torque.data(), &report);
  if (st != RSL_OK) {
    const size_t c = report.first_failed < n ? (size_t) report.first_failed : 0;
    const int i = chunk.atoms[c];
    library_error("rsl_batch_step_walls", st, atom->tag_enable ? atom->tag[i] : (tagint) i,
                  side[i]);
  }
  double **f = atom->f;
  double **torque = atom->torque;
  for (size_t c = 0; c < n; c++) {
    const int i = chunk.atoms[c];
    f[i][0] += chunk_force[c].x;
    f[i][1] += chunk_force[c].y;
    f[i][2] += chunk_force[c].z;
    torque[i][0] += chunk_torque[c].x;
    torque[i][1] += chunk_torque[c].y;
    torque[i][2] += chunk_torque[c].z;
    if (energy) {
      const rsl_contact_energy &e = chunk_energy[c];
      energy->tally(i, 1.0, true, e, chunk.normal_dissipated[c], chunk.normal_elastic[c]);
      spring_energy[4 * i] = e.elastic_sliding;
      spring_energy[4 * i + 1] = e.elastic_rolling;
      spring_energy[4 * i + 2] = e.elastic_twisting;
      spring_energy[4 * i + 3] = chunk.normal_elastic[c];
    }
  }
  chunk.clear();
}

// Atom i's wall contact ended: its history is dropped, and the energy its springs held after
// its last step is dissipated by the sliders (as the pair style tallies an ended contact).
void FixWallGranRollslide::end_contact(int i)
{
  if (energy) {
    rsl_contact_energy e;
    memset(&e, 0, sizeof e);
    e.slider_sliding = spring_energy[4 * i];
    e.slider_rolling = spring_energy[4 * i + 1];
    e.slider_twisting = spring_energy[4 * i + 2];
    energy->tally(i, 1.0, true, e, 0.0, 0.0);
    // A JKR neck breaking loses its normal force's potential (other models' contacts end at
    // zero overlap, with none).
    if (coeffs.normal == granular::JKR) energy->tally_neck_wall(i, spring_energy[4 * i + 3]);
  }
  rsl_contact_state_init(&history[i]);
  for (int k = 0; k < 4; k++) spring_energy[4 * i + k] = 0.0;
  side[i] = NO_WALL;
}

void FixWallGranRollslide::write_restart(FILE *fp)
{
  if (comm->me == 0) {
    const double list[1] = {(double) time_origin};
    const int size = sizeof list;
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list, sizeof(double), 1, fp);
  }
}

void FixWallGranRollslide::restart(char *buf)
{
  double t;
  memcpy(&t, buf, sizeof t);
  time_origin = (bigint) t;
}

double FixWallGranRollslide::memory_usage()
{
  return (double) history.capacity() * sizeof(rsl_contact_state) +
      (double) side.capacity() * sizeof(int) + (double) spring_energy.capacity() * sizeof(double);
}

void FixWallGranRollslide::grow_arrays(int nmax)
{
  if ((int) history.size() < nmax) {
    history.resize(nmax);
    side.resize(nmax, NO_WALL);
    spring_energy.resize(4 * (size_t) nmax, 0.0);
  }
}

void FixWallGranRollslide::copy_arrays(int i, int j, int)
{
  history[j] = history[i];
  side[j] = side[i];
  for (int k = 0; k < 4; k++) spring_energy[4 * j + k] = spring_energy[4 * i + k];
}

void FixWallGranRollslide::set_arrays(int i)
{
  rsl_contact_state_init(&history[i]);
  side[i] = NO_WALL;
  for (int k = 0; k < 4; k++) spring_energy[4 * i + k] = 0.0;
}

void FixWallGranRollslide::pack_atom(int i, double *buf) const
{
  const rsl_contact_state &s = history[i];
  const double values[ATOM_DOUBLES] = {
      s.sliding_spring.x,   s.sliding_spring.y,   s.sliding_spring.z,
      s.rolling_spring.x,   s.rolling_spring.y,   s.rolling_spring.z,
      s.twisting_angle,
      s.model_memory.x, s.model_memory.y, s.model_memory.z,
      s.previous_normal.x,  s.previous_normal.y,  s.previous_normal.z,
      (double) s.slip_flags, (double) side[i],
      spring_energy[4 * i], spring_energy[4 * i + 1], spring_energy[4 * i + 2],
      spring_energy[4 * i + 3]};
  memcpy(buf, values, sizeof values);
}

void FixWallGranRollslide::unpack_atom(const double *b, int i)
{
  rsl_contact_state &s = history[i];
  s.sliding_spring = {b[0], b[1], b[2]};
  s.rolling_spring = {b[3], b[4], b[5]};
  s.twisting_angle = b[6];
  s.model_memory = {b[7], b[8], b[9]};
  s.previous_normal = {b[10], b[11], b[12]};
  s.slip_flags = (uint32_t) b[13];
  s.reserved = 0;
  side[i] = (int) b[14];
  for (int k = 0; k < 4; k++) spring_energy[4 * i + k] = b[15 + k];
}

int FixWallGranRollslide::pack_exchange(int i, double *buf)
{
  pack_atom(i, buf);
  return ATOM_DOUBLES;
}

int FixWallGranRollslide::unpack_exchange(int nlocal, double *buf)
{
  grow_arrays(nlocal + 1);
  unpack_atom(buf, nlocal);
  return ATOM_DOUBLES;
}

int FixWallGranRollslide::pack_restart(int i, double *buf)
{
  // buf[0] is the length of this fix's values, read by Atom to skip them.
  buf[0] = 1 + ATOM_DOUBLES;
  pack_atom(i, &buf[1]);
  return 1 + ATOM_DOUBLES;
}

void FixWallGranRollslide::unpack_restart(int nlocal, int nth)
{
  grow_arrays(nlocal + 1);
  double **extra = atom->extra;
  int m = 0;
  for (int k = 0; k < nth; k++) m += static_cast<int>(extra[nlocal][m]);
  if (static_cast<int>(extra[nlocal][m]) == 1 + OLD_ATOM_DOUBLES) {
    // Written before the normal energy was kept: read with it 0.
    double b[ATOM_DOUBLES] = {};
    memcpy(b, &extra[nlocal][m + 1], OLD_ATOM_DOUBLES * sizeof(double));
    unpack_atom(b, nlocal);
  } else
    unpack_atom(&extra[nlocal][m + 1], nlocal);
}

int FixWallGranRollslide::size_restart(int)
{
  return 1 + ATOM_DOUBLES;
}

int FixWallGranRollslide::maxsize_restart()
{
  return 1 + ATOM_DOUBLES;
}
