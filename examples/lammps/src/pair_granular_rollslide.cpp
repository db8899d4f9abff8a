// pair_style granular/rollslide: see pair_granular_rollslide.h.
//
// Conventions: LAMMPS' pair (i, j) is the library's (body 1, body 2); LAMMPS' normal
// `(x_i - x_j)/r` is the library's `-n`; the library returns the force on body 1 (= i), whole
// (normal + sliding), and the torques on both bodies. The neighbour list is always a newton
// off list (each pair with a ghost atom is computed by both ranks, each applying the loads to
// its own atom), whatever `newton_pair` says, so that no contact history has to be sent back
// to a ghost atom's owner: each rank keeps the history of its own atoms' contacts, in its
// atom's perspective (rsl_contact_state_swap gives the partner's).
//
// Energy. When a compute rollslide/energy is defined (or a compute pair/local, which calls
// single()), init_style builds the library models with energy tracking and every contact pass
// collects, per stepped contact, the library's energy terms (params.energy of both batch calls,
// out.energy of the setup pass's rsl_contact_step), the normal dashpot's dissipation
// (granular::normal_dissipation: the dashpot force actually applied, limit_damping's clip
// included, times the normal displacement rate of the step, times dt) and the normal spring's
// energy. Each contact is tallied half to atom i and half to atom j if j is local: a ghost j's
// owner computes the same contact from its side (the list is newton off), and tallies its half
// there. A contact found ended (its history about to be dropped) is tallied once more: the
// energy its springs held after its last step (kept per entry by the history fix, which moves
// it with the history) is dissipated by its sliders. A run's setup pass is no time step: its
// dashpot terms are left out (nothing moves over it); the `lammps` preset's setup pass writes
// the history (LAMMPS' clip rules do), so its slider and transport terms (a spring clipped or
// transported by the pass) are kept, while the objective preset's writes nothing, so nothing
// is dissipated and the springs' elastic energy is what they keep (the energy after the clip
// plus the clip's). Without either compute none of this runs: the models compute no energy and
// the contact loop is its instantiation without it.
#include "pair_granular_rollslide.h"

#include "compute_rollslide_energy.h"
#include "fix_rollslide_history.h"
#include "granular_model.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neigh_request.h"
#include "neighbor.h"
#include "update.h"
#include "utils.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

namespace {

// Writes an atom's sphere record in place, field by field. (Building it in a local and copying
// it made GCC store it in doubles and reload it in 16-byte pieces, a store-forwarding stall per
// record.)
void fill_sphere(rsl_sphere &s, const double *x, const double *v, const double *w, double r)
{
  s.position.x = x[0];
  s.position.y = x[1];
  s.position.z = x[2];
  s.velocity.x = v[0];
  s.velocity.y = v[1];
  s.velocity.z = v[2];
  s.angular_velocity.x = w[0];
  s.angular_velocity.y = w[1];
  s.angular_velocity.z = w[2];
  s.radius = r;
}

}    // namespace

PairGranularRollslide::PairGranularRollslide(LAMMPS *lmp) : Pair(lmp)
{
  // single(): the normal force over r, and in svector each contact's dissipation rates of its
  // last pass (energy/time): normal damping, sliding dashpot, sliding friction, rolling dashpot,
  // rolling friction, twisting dashpot, twisting friction.
  single_enable = 1;
  single_extra = NRATES;
  svector = new double[single_extra];
  restartinfo = 0;    // pair_style and pair_coeff are given again after read_restart
  no_virial_fdotr_compute = 1;    // the list is newton off: tallied per pair
  finitecutflag = 1;
  // The history fix is created here, before the input's other fixes, so that its
  // pre_exchange() runs before any fix that moves or deletes atoms in theirs (as LAMMPS'
  // pair granular places its own history fix). A restart file's history is read when the fix
  // is created (same ID and style).
  modify->add_fix(std::string(FixRollslideHistory::ID) + " all " + FixRollslideHistory::STYLE);
  history = static_cast<FixRollslideHistory *>(modify->fix[modify->find_fix(FixRollslideHistory::ID)]);
  history->pair = this;
}

PairGranularRollslide::~PairGranularRollslide()
{
  free_models();
  delete[] svector;
  if (modify->find_fix(FixRollslideHistory::ID) >= 0) modify->delete_fix(FixRollslideHistory::ID);
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
  }
}

void PairGranularRollslide::fail(const std::string &message)
{
  error->all(FLERR, std::string("pair_style granular/rollslide: ") + message);
}

void PairGranularRollslide::library_error(const char *call, int32_t status, tagint id1, tagint id2)
{
  // error->one: the failing contact is on this rank only.
  error->one(FLERR,
             std::string("pair_style granular/rollslide: ") + call + " failed for the contact of atoms " +
                 std::to_string(id1) + " and " + std::to_string(id2) + ": " + rsl_status_str(status) +
                 " (" + rsl_last_error_message() + ")");
}

void PairGranularRollslide::free_models()
{
  for (Group &g : groups)
    if (g.owned) rsl_model_free(g.model);
  groups.clear();
  for (rsl_model *&m : models) {
    rsl_model_free(m);
    m = nullptr;
  }
}

void PairGranularRollslide::allocate()
{
  allocated = 1;
  ntypes = atom->ntypes;
  int n = ntypes;
  memory->create(setflag, n + 1, n + 1, "pair:setflag");
  memory->create(cutsq, n + 1, n + 1, "pair:cutsq");
  for (int i = 1; i <= n; i++)
    for (int j = i; j <= n; j++) setflag[i][j] = 0;
  coeffs.assign((n + 1) * (n + 1), Coeffs());
  models.assign((n + 1) * (n + 1), nullptr);
  maxrad.assign(n + 1, 0.0);
}

void PairGranularRollslide::settings(int narg, char **arg)
{
  if (narg > 1) fail("expected `pair_style granular/rollslide [objective|lammps]`");
  preset = RSL_PRESET_OBJECTIVE;
  if (narg == 1) {
    if (strcmp(arg[0], "lammps") == 0)
      preset = RSL_PRESET_LAMMPS_2021;
    else if (strcmp(arg[0], "objective") != 0)
      fail(std::string("unknown keyword '") + arg[0] + "' (expected objective or lammps)");
  }
}

// pair_coeff I J <pair granular's keywords for the supported subset>
void PairGranularRollslide::coeff(int narg, char **arg)
{
  if (narg < 2) fail("pair_coeff needs two types");
  if (!allocated) allocate();
  int ilo, ihi, jlo, jhi;
  utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
  utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);

  Coeffs c;
  granular::parse(lmp, narg, arg, 2, c, "pair_coeff", [this](const std::string &m) { fail(m); });

  int count = 0;
  for (int i = ilo; i <= ihi; i++)
    for (int j = (jlo > i ? jlo : i); j <= jhi; j++) {
      at(i, j) = c;
      at(j, i) = c;
      setflag[i][j] = 1;
      count++;
    }
  if (count == 0) fail("pair_coeff: no type pair set");
}

void PairGranularRollslide::init_style()
{
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    fail("needs atom_style sphere (radius, rmass, omega, torque)");
  if (comm->ghost_velocity == 0) fail("needs ghost atoms to store velocities (comm_modify vel yes)");
  if (atom->tag_enable == 0) fail("needs atom IDs");
  for (int i = 0; i < modify->nfix; i++)
    if (modify->fix[i]->rigid_flag)
      fail(std::string("rigid bodies (fix ") + modify->fix[i]->style + ") are not supported");

  // A newton off list sized by the particle radii, whatever newton_pair says.
  int irequest = neighbor->request(this, instance_me);
  neighbor->requests[irequest]->size = 1;
  neighbor->requests[irequest]->newton = 2;

  dt = update->dt;

  int ifreeze = modify->find_fix_by_style("^freeze");
  freeze_group_bit = ifreeze < 0 ? 0 : modify->fix[ifreeze]->groupbit;

  // Largest radius per type, including the particles fix pour / fix deposit will insert.
  std::vector<double> local(ntypes + 1, 0.0);
  for (int ifix = 0; ifix < modify->nfix; ifix++) {
    const char *style = modify->fix[ifix]->style;
    if (strncmp(style, "pour", 4) != 0 && strncmp(style, "deposit", 7) != 0) continue;
    for (int t = 1; t <= ntypes; t++) {
      int itype = t;
      double *r = static_cast<double *>(modify->fix[ifix]->extract("radius", itype));
      if (r && *r > local[t]) local[t] = *r;
    }
  }
  for (int i = 0; i < atom->nlocal; i++)
    if (atom->radius[i] > local[atom->type[i]]) local[atom->type[i]] = atom->radius[i];
  MPI_Allreduce(local.data(), maxrad.data(), ntypes + 1, MPI_DOUBLE, MPI_MAX, world);

  // Unset cross pairs: the same coefficients on both sides only (no mixing rules).
  for (int i = 1; i <= ntypes; i++)
    for (int j = i + 1; j <= ntypes; j++)
      if (!setflag[i][j]) {
        if (!at(i, i).set || !at(j, j).set || !(at(i, i) == at(j, j)))
          fail("pair_coeff " + std::to_string(i) + " " + std::to_string(j) +
               " must be given (coefficients are not mixed)");
        at(i, j) = at(j, i) = at(i, i);
      }

  // Energy: the first compute rollslide/energy receives the contacts; a compute pair/local
  // reads single(), whose dissipation rates need the energy terms too.
  energy = nullptr;
  per_contact = false;
  for (int i = 0; i < modify->ncompute; i++) {
    if (energy == nullptr && strcmp(modify->compute[i]->style, ComputeRollslideEnergy::STYLE) == 0)
      energy = static_cast<ComputeRollslideEnergy *>(modify->compute[i]);
    if (strcmp(modify->compute[i]->style, "pair/local") == 0) per_contact = true;
  }
  track = energy != nullptr || per_contact;
  if (!per_contact) {
    contact_rates.clear();
    contact_rates.shrink_to_fit();
    rates_pass.clear();
    rates_pass.shrink_to_fit();
    list_index.clear();
  }

  // One library model per type pair, and the groups of the batch calls (see Group).
  free_models();
  for (int i = 1; i <= ntypes; i++)
    for (int j = 1; j <= ntypes; j++) {
      if (!at(i, j).set) fail("pair_coeff " + std::to_string(i) + " " + std::to_string(j) + " is missing");
      models[i * (ntypes + 1) + j] = new_model(at(i, j), i, j);
    }
  any_jkr = false;
  for (int i = 1; i <= ntypes; i++)
    for (int j = 1; j <= ntypes; j++) any_jkr = any_jkr || at(i, j).normal == granular::JKR;
  build_groups();

  direct.resize(true, track);
  paired.resize(false, track);
}

// A library model of coefficients `c` (those of type pair i j, named in the error).
rsl_model *PairGranularRollslide::new_model(const Coeffs &c, int i, int j)
{
  std::string message;
  rsl_model *m = granular::new_model(preset, c, track, message);
  if (m == nullptr)
    fail("pair_coeff " + std::to_string(i) + " " + std::to_string(j) +
         ": the library refused the coefficients: " + message);
  return m;
}

// Groups the type pairs I <= J by law set (the library laws new_model sets: rolling, twisting,
// what the sliding spring stores), in the order of their first pair; (J, I) goes with (I, J),
// whose coefficients it has. A group of several pairs gets a model of its own with a table of
// their models' coefficient sets, set k being the group's k-th pair.
void PairGranularRollslide::build_groups()
{
  const int n = ntypes + 1;
  slots.assign(n * n, Slot());
  groups.clear();
  std::vector<std::vector<int>> members;    // per group: its pairs' indices (itype * n + jtype)
  for (int i = 1; i <= ntypes; i++)
    for (int j = i; j <= ntypes; j++) {
      const Coeffs &c = at(i, j);
      size_t g = 0;
      auto same_laws = [&](const Coeffs &o) {
        return o.rolling == c.rolling && o.twist == c.twist &&
            granular::sliding_history(o.tangential) == granular::sliding_history(c.tangential);
      };
      while (g < members.size() && !same_laws(coeffs[members[g][0]])) g++;
      if (g == members.size()) {
        members.emplace_back();
        groups.emplace_back();
      }
      Slot slot;
      slot.group = (int) g;
      slot.material = (uint32_t) members[g].size();
      slots[i * n + j] = slots[j * n + i] = slot;
      members[g].push_back(i * n + j);
      groups[g].kt = groups[g].kt || granular::is_mindlin(c.tangential);
      groups[g].gammat = groups[g].gammat || c.damping != granular::VELOCITY;
    }
  for (size_t g = 0; g < groups.size(); g++) {
    const int first = members[g][0];
    if (members[g].size() == 1) {
      groups[g].model = models[first];
      continue;
    }
    // The laws of the group's first pair; the table gives every contact its own pair's values.
    groups[g].model = new_model(coeffs[first], first / n, first % n);
    groups[g].owned = true;
    std::vector<const rsl_model *> sets;
    for (int k : members[g]) sets.push_back(models[k]);
    int32_t st = rsl_model_set_materials(groups[g].model, sets.data(), sets.size());
    if (st != RSL_OK)
      fail("pair_coeff " + std::to_string(first / n) + " " + std::to_string(first % n) +
           ": the library refused the table of its law set's type pairs: " + rsl_status_str(st) +
           " (" + rsl_last_error_message() + ")");
  }
}

double PairGranularRollslide::init_one(int i, int j)
{
  const Coeffs &c = at(i, j);
  if (c.cutoff >= 0.0) return c.cutoff;
  double cut = maxrad[i] + maxrad[j];
  // JKR: a neck holds until the pull-off distance (the largest radii's, which is the largest),
  // so the neighbour list reaches that far.
  if (c.normal == granular::JKR && maxrad[i] > 0.0 && maxrad[j] > 0.0)
    cut -= granular::jkr_pulloff_overlap(0.75 * c.kn, c.coh,
                                         maxrad[i] * maxrad[j] / (maxrad[i] + maxrad[j]));
  return cut > 0.0 ? cut : 0.0;
}

void PairGranularRollslide::apply(int i, int j, const double del[3], const rsl_vec3 &force1,
                                  const rsl_vec3 &torque1, const rsl_vec3 &torque2)
{
  double **f = atom->f;
  double **torque = atom->torque;
  const int nlocal = atom->nlocal;
  f[i][0] += force1.x;
  f[i][1] += force1.y;
  f[i][2] += force1.z;
  torque[i][0] += torque1.x;
  torque[i][1] += torque1.y;
  torque[i][2] += torque1.z;
  // A ghost j's owner computes this contact itself (newton off list).
  if (j < nlocal) {
    f[j][0] -= force1.x;
    f[j][1] -= force1.y;
    f[j][2] -= force1.z;
    torque[j][0] += torque2.x;
    torque[j][1] += torque2.y;
    torque[j][2] += torque2.z;
  }
  if (evflag) ev_tally_xyz(i, j, nlocal, 0, 0.0, 0.0, force1.x, force1.y, force1.z, del[0], del[1], del[2]);
}

void PairGranularRollslide::Chunk::resize(bool is_direct, bool with_energy)
{
  pending.resize(CHUNK);
  pairs.resize(is_direct ? 2 * CHUNK : 0);
  body1.resize(is_direct ? 0 : CHUNK);
  body2.resize(is_direct ? 0 : CHUNK);
  normal_force.resize(CHUNK);
  sliding_stiffness.resize(CHUNK);
  sliding_damping.resize(CHUNK);
  material.resize(CHUNK);
  index.resize(is_direct ? CHUNK : 0);
  state.resize(is_direct ? 0 : CHUNK);
  loads.resize(is_direct ? 0 : CHUNK);
  energy.resize(with_energy ? CHUNK : 0);
  normal_dissipated.resize(with_energy ? CHUNK : 0);
  normal_elastic.resize(with_energy ? CHUNK : 0);
}

// Steps the direct chunk in one rsl_batch_step_indexed call (with the chunk's per-contact k_t and
// gamma_t when its law has them), which steps each contact's history where the fix keeps it
// (its entries come in increasing order, as the call requires) and adds the loads to both
// atoms' force and torque in the chunk's order.
void PairGranularRollslide::flush_direct()
{
  Chunk &ch = direct;
  const int n = ch.n;
  if (n == 0) return;
  rsl_batch_report report;
  rsl_batch_contact_params params = chunk_params(ch);
  const size_t nall = (size_t) atom->nlocal + atom->nghost;
  // atom->f and atom->torque hold 3 contiguous doubles per atom, the layout of rsl_vec3.
  rsl_vec3 *f = reinterpret_cast<rsl_vec3 *>(atom->f[0]);
  rsl_vec3 *t = reinterpret_cast<rsl_vec3 *>(atom->torque[0]);
  int32_t st = rsl_batch_step_indexed(groups[chunk_group].model, spheres.data(), nall, ch.pairs.data(), n,
                                      ch.normal_force.data(), nullptr, &params, dt, nullptr,
                                      history->state.data(), history->state.size(),
                                      ch.index.data(), f, t, &report);
  if (st != RSL_OK) chunk_error("rsl_batch_step_indexed", st, report, ch);
  if (track) tally_chunk(ch);
  ch.n = 0;
}

// Copies the stored histories of the paired chunk's contacts into the chunk.
void PairGranularRollslide::load_states(Chunk &ch)
{
  const rsl_contact_state *states = history->state.data();
  for (int k = 0; k < ch.n; k++) ch.state[k] = states[ch.pending[k].e];
}

// A LAMMPS error for the first contact a chunk's library call skipped.
void PairGranularRollslide::chunk_error(const char *call, int32_t status,
                                        const rsl_batch_report &report, const Chunk &ch)
{
  size_t bad = report.first_failed < (uint64_t) ch.n ? report.first_failed : 0;
  library_error(call, status, atom->tag[ch.pending[bad].i], atom->tag[ch.pending[bad].j]);
}

// The per-contact coefficients of a chunk, for its group: the sliding ones its law set has
// per contact, and each contact's set in the group's table (if it has one).
rsl_batch_contact_params PairGranularRollslide::chunk_params(Chunk &ch) const
{
  const Group &g = groups[chunk_group];
  rsl_batch_contact_params params{};
  params.sliding_stiffness = g.kt ? ch.sliding_stiffness.data() : nullptr;
  params.sliding_damping = g.gammat ? ch.sliding_damping.data() : nullptr;
  params.material = g.owned ? ch.material.data() : nullptr;
  params.energy = track ? ch.energy.data() : nullptr;
  return params;
}

// Steps the paired chunk in one rsl_batch_step_contacts_params call, then applies its loads in
// neighbour-list order.
void PairGranularRollslide::flush_paired()
{
  Chunk &ch = paired;
  const int n = ch.n;
  if (n == 0) return;
  load_states(ch);
  rsl_batch_report report;
  rsl_batch_contact_params params = chunk_params(ch);
  int32_t st = rsl_batch_step_contacts_params(groups[chunk_group].model, ch.body1.data(), ch.body2.data(), n,
                                              ch.normal_force.data(), nullptr, &params, dt, nullptr,
                                              ch.state.data(), ch.loads.data(), &report);
  if (st != RSL_OK) chunk_error("rsl_batch_step_contacts_params", st, report, ch);
  rsl_contact_state *states = history->state.data();
  for (int k = 0; k < n; k++) {
    const Pending &p = ch.pending[k];
    states[p.e] = ch.state[k];
    apply(p.i, p.j, p.del, ch.loads[k].force1, ch.loads[k].torque1, ch.loads[k].torque2);
  }
  if (track) tally_chunk(ch);
  ch.n = 0;
}

void PairGranularRollslide::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);
  history->ensure_entries();
  dt = update->dt;
  const bool setup = update->setupflag != 0;
  if (!track) {
    compute_contacts<false>(setup);
    return;
  }
  if (energy) energy->begin_step();
  if (per_contact) {
    // single() finds a pair's entry through its atom's place in the list.
    if (contact_rates.size() < NRATES * history->state.size()) {
      contact_rates.resize(NRATES * history->state.size());
      rates_pass.resize(history->state.size(), 0);
    }
    pass++;
    list_index.assign(atom->nlocal, -1);
    for (int ii = 0; ii < list->inum; ii++) list_index[list->ilist[ii]] = ii;
  }
  compute_contacts<true>(setup);
}

// The contact pass; ENERGY: with the energy terms (track).
template <bool ENERGY> void PairGranularRollslide::compute_contacts(bool setup)
{
  double **x = atom->x;
  double **v = atom->v;
  double **omega = atom->omega;
  double *radius = atom->radius;
  double *rmass = atom->rmass;
  int *type = atom->type;
  int *mask = atom->mask;
  tagint *tag = atom->tag;

  const int inum = list->inum;
  int *ilist = list->ilist;
  int *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;
  unsigned char *touch = history->touch.data();
  rsl_contact_state *states = history->state.data();
  direct.n = paired.n = 0;
  chunk_group = -1;
  const int nlocal = atom->nlocal;
  // Contacts between two local atoms go to the direct chunks, stepped from one sphere record
  // per atom, except on steps that tally energy or virial (which need each pair's force).
  const bool use_direct = !setup && !evflag;
  if (use_direct) {
    const int nall = nlocal + atom->nghost;
    if ((int) spheres.size() < nall) spheres.resize(nall);
    for (int k = 0; k < nall; k++) fill_sphere(spheres[k], x[k], v[k], omega[k], radius[k]);
  }

  const bool jkr_necks = any_jkr;    // a local: the loop tests it without reloading it
  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    const int itype = type[i];
    const double radi = radius[i];
    int *jlist = firstneigh[i];
    const int jnum = numneigh[i];
    const bigint base = history->first[ii];
    for (int jj = 0; jj < jnum; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      const bigint e = base + jj;
      const double delx = x[i][0] - x[j][0];
      const double dely = x[i][1] - x[j][1];
      const double delz = x[i][2] - x[j][2];
      const double rsq = delx * delx + dely * dely + delz * delz;
      const double radj = radius[j];
      const double radsum = radi + radj;
      // The contact's reach: the touching distance, and for a JKR contact that touched (its
      // neck) the pull-off distance radsum - delta_pulloff (delta_pulloff < 0), as LAMMPS'.
      // (Without JKR, nothing of j but its position and radius is read before it touches.)
      double reach = radsum;
      if (jkr_necks && touch[e]) {
        const Coeffs &cj = at(itype, type[j]);
        if (cj.normal == granular::JKR)
          reach = radsum -
              granular::jkr_pulloff_overlap(0.75 * cj.kn, cj.coh, radi * radj / radsum);
      }
      if (rsq >= reach * reach) {
        // Not touching: the contact (if any) ends and its history is dropped, as LAMMPS does.
        if (touch[e]) {
          if (ENERGY) release(i, j, e);
          touch[e] = 0;
          rsl_contact_state_init(&states[e]);
        }
        continue;
      }
      const int jtype = type[j];
      const Coeffs &c = at(itype, jtype);

      // The normal force, as pair granular computes it (n from j to i here).
      const double r = sqrt(rsq);
      const double rinv = 1.0 / r;
      const double nx = delx * rinv, ny = dely * rinv, nz = delz * rinv;
      const double vnnr =
          (v[i][0] - v[j][0]) * nx + (v[i][1] - v[j][1]) * ny + (v[i][2] - v[j][2]) * nz;
      double mi = rmass[i], mj = rmass[j];
      double meff = mi * mj / (mi + mj);
      if (mask[i] & freeze_group_bit) meff = mj;
      if (mask[j] & freeze_group_bit) meff = mi;
      const double Reff = radi * radj / radsum;
      const granular::NormalForce nf = granular::normal_force(c, radsum - r, Reff, meff, vnnr);
      const double Fntot = nf.force;

      touch[e] = 1;
      const bool per_gammat = nf.per_contact_damping, per_kt = nf.per_contact_stiffness;
      const double gammat = nf.sliding_damping;
      const double kt = nf.sliding_stiffness;
      if (!setup && !nf.cohesive) {
        // Gathered for one batch call per chunk (one group, hence one law set, per chunk).
        const Slot &slot = slots[itype * (ntypes + 1) + jtype];
        if (slot.group != chunk_group) {
          flush();
          chunk_group = slot.group;
        }
        // The fields both kinds of chunk keep; returns the contact's place in the chunk.
        // (Written once per kind below, so that each copy addresses its chunk's arrays
        // directly.)
        auto join = [&](Chunk &ch) {
          const int k = ch.n++;
          // The flush reads this contact's history (in place, or copying it into the chunk)
          // up to CHUNK contacts later. The histories of all neighbour pairs are far larger than
          // the cache, and the flush would wait on each one in turn: fetched now (for writing:
          // the step writes it back), it is in cache by then.
          const char *h = reinterpret_cast<const char *>(&states[e]);
          __builtin_prefetch(h, 1);
          __builtin_prefetch(h + 64, 1);
          __builtin_prefetch(h + sizeof(rsl_contact_state) - 1, 1);
          Pending &p = ch.pending[k];
          p.i = i;
          p.j = j;
          p.e = e;
          p.del[0] = delx;
          p.del[1] = dely;
          p.del[2] = delz;
          ch.normal_force[k] = Fntot;
          ch.sliding_stiffness[k] = kt;
          ch.sliding_damping[k] = gammat;
          ch.material[k] = slot.material;
          if (ENERGY) {
            ch.normal_dissipated[k] = granular::normal_dissipation(nf, vnnr, dt);
            ch.normal_elastic[k] = nf.elastic;
          }
          return k;
        };
        if (use_direct && j < nlocal) {
          if (direct.n == CHUNK) flush_direct();
          const int k = join(direct);
          direct.index[k] = (size_t) e;
          direct.pairs[2 * k] = (uint32_t) i;
          direct.pairs[2 * k + 1] = (uint32_t) j;
        } else {
          if (paired.n == CHUNK) flush_paired();
          const int k = join(paired);
          fill_sphere(paired.body1[k], x[i], v[i], omega[i], radi);
          fill_sphere(paired.body2[k], x[j], v[j], omega[j], radj);
        }
        continue;
      }
      // Per contact: the setup pass (LAMMPS' setup step stores no history increment), and the
      // cohesive models' contacts, whose limits take LAMMPS' Fncrit (|Fne + 2 F_pulloff|), which
      // the batch calls have no per-contact input for (one library call per contact: slower
      // than the batch calls, but the only way to pass it).
      flush();
      rsl_contact_input in;
      memset(&in, 0, sizeof in);
      in.normal_force = Fntot;
      in.dt = dt;
      if (setup) in.flags |= RSL_INPUT_SETUP;
      if (nf.cohesive) {
        in.flags |= RSL_INPUT_LIMIT_FORCE;
        in.limit_force = nf.limit_force;
        // Mindlin's k_t = kt a and Marshall's twisting take JKR's a (the library's own would be
        // sqrt(delta R), undefined beyond touching).
        in.contact_radius = nf.contact_radius;
      }
      if (per_gammat) {
        in.flags |= RSL_INPUT_SLIDING_DAMPING;
        in.sliding_damping = gammat;
      }
      if (per_kt) {
        in.flags |= RSL_INPUT_SLIDING_STIFFNESS;
        in.sliding_stiffness = kt;
      }
      rsl_sphere s1, s2;
      fill_sphere(s1, x[i], v[i], omega[i], radi);
      fill_sphere(s2, x[j], v[j], omega[j], radj);
      rsl_contact_loads out;
      int32_t st = rsl_contact_step(model(itype, jtype), &s1, &s2, &in, &states[e], &out);
      if (st != RSL_OK) library_error("rsl_contact_step", st, tag[i], tag[j]);
      const double del[3] = {delx, dely, delz};
      apply(i, j, del, out.force1, out.torque1, out.torque2);
      if (ENERGY && !setup) {
        tally(i, j, e, out.energy, granular::normal_dissipation(nf, vnnr, dt), nf.elastic);
      } else if (ENERGY) {
        // No time passes in the setup pass: no dashpot dissipates (see "Energy" above).
        rsl_contact_energy en = out.energy;
        en.dashpot_sliding = en.dashpot_rolling = en.dashpot_twisting = 0.0;
        if (preset != RSL_PRESET_LAMMPS_2021) {
          // The objective preset's setup pass writes no state: the springs keep what they held
          // (the clip's energy, E_trial - E_new, stays in them), nothing is dissipated.
          en.elastic_sliding += en.slider_sliding;
          en.elastic_rolling += en.slider_rolling;
          en.elastic_twisting += en.slider_twisting;
          en.slider_sliding = en.slider_rolling = en.slider_twisting = en.transport = 0.0;
          en.stiffness_change = 0.0;
        }
        tally(i, j, e, en, 0.0, nf.elastic);
      }
    }
  }
  flush();
}

// One stepped contact's energy: half to each local atom (the compute), and its dissipation
// rates into its entry (single()).
void PairGranularRollslide::tally(int i, int j, bigint e, const rsl_contact_energy &en,
                                  double normal_dissipated, double normal_elastic)
{
  // Half to i, half to j if local: a ghost j's owner tallies its half itself (it computes the
  // contact too: newton off list).
  if (energy) energy->tally_pair(i, j, atom->nlocal, en, normal_dissipated, normal_elastic);
  double *el = &history->elastic[FixRollslideHistory::ENERGIES * e];
  el[0] = en.elastic_sliding;
  el[1] = en.elastic_rolling;
  el[2] = en.elastic_twisting;
  el[3] = normal_elastic;
  if (per_contact) {
    rates_pass[e] = pass;
    double *r = &contact_rates[NRATES * e];
    r[0] = normal_dissipated / dt;
    r[1] = en.dashpot_sliding / dt;
    r[2] = en.slider_sliding / dt;
    r[3] = en.dashpot_rolling / dt;
    r[4] = en.slider_rolling / dt;
    r[5] = en.dashpot_twisting / dt;
    r[6] = en.slider_twisting / dt;
  }
}

// A contact that ended (its history is about to be dropped): the energy its springs held after
// its last step is dissipated by its sliders (with no contact, every friction limit is zero).
//
// A JKR neck breaking at pull-off also loses its normal force's potential U(a) of its last
// step (the energy the neck held, counted from the touch): the neck-breaking column. (Other
// models' contacts end at zero overlap, where their normal potential is zero.)
void PairGranularRollslide::release(int i, int j, bigint e)
{
  const double *el = &history->elastic[FixRollslideHistory::ENERGIES * e];
  rsl_contact_energy en;
  memset(&en, 0, sizeof en);
  en.slider_sliding = el[0];
  en.slider_rolling = el[1];
  en.slider_twisting = el[2];
  const double neck = at(atom->type[i], atom->type[j]).normal == granular::JKR ? el[3] : 0.0;
  if (energy && neck != 0.0) energy->tally_neck_pair(i, j, atom->nlocal, neck);
  tally(i, j, e, en, 0.0, 0.0);
}

void PairGranularRollslide::tally_chunk(const Chunk &ch)
{
  for (int k = 0; k < ch.n; k++) {
    const Pending &p = ch.pending[k];
    tally(p.i, p.j, p.e, ch.energy[k], ch.normal_dissipated[k], ch.normal_elastic[k]);
  }
}

// The history entry of the contact of local atom i and atom j (i's list, or j's if j is local),
// or -1.
bigint PairGranularRollslide::find_entry(int i, int j) const
{
  for (int side = 0; side < 2; side++) {
    const int a = side == 0 ? i : j, b = side == 0 ? j : i;
    if (a >= (int) list_index.size() || list_index[a] < 0) continue;
    const int ii = list_index[a];
    const int *jlist = list->firstneigh[a];
    for (int jj = 0; jj < list->numneigh[a]; jj++)
      if ((jlist[jj] & NEIGHMASK) == b) return history->first[ii] + jj;
  }
  return -1;
}

// For compute pair/local: the normal force over r (fforce, as pair granular's single gives it;
// 0 for pairs not touching), the energy 0, and in svector the contact's dissipation rates in
// the last contact pass (energy/time; zero for pairs not stepped or released in that pass, and
// without a compute pair/local at the run's init).
double PairGranularRollslide::single(int i, int j, int itype, int jtype, double rsq, double,
                                     double, double &fforce)
{
  for (int m = 0; m < single_extra; m++) svector[m] = 0.0;
  fforce = 0.0;
  if (per_contact) {
    const bigint e = find_entry(i, j);
    if (e >= 0 && (size_t) e < rates_pass.size() && rates_pass[e] == pass)
      for (int m = 0; m < NRATES; m++) svector[m] = contact_rates[NRATES * e + m];
  }
  double *radius = atom->radius;
  const double radsum = radius[i] + radius[j];
  if (rsq >= radsum * radsum) {
    // A JKR neck beyond touching (found only with a compute pair/local at the run's init).
    const Coeffs &c = at(itype, jtype);
    if (c.normal != granular::JKR || !per_contact) return 0.0;
    const bigint e = find_entry(i, j);
    if (e < 0 || !history->touch[e]) return 0.0;
    const double reach =
        radsum - granular::jkr_pulloff_overlap(0.75 * c.kn, c.coh, radius[i] * radius[j] / radsum);
    if (rsq >= reach * reach) return 0.0;
  }

  double **x = atom->x;
  double **v = atom->v;
  double *rmass = atom->rmass;
  int *mask = atom->mask;
  const double r = sqrt(rsq);
  const double rinv = 1.0 / r;
  const double nx = (x[i][0] - x[j][0]) * rinv, ny = (x[i][1] - x[j][1]) * rinv,
               nz = (x[i][2] - x[j][2]) * rinv;
  const double vnnr = (v[i][0] - v[j][0]) * nx + (v[i][1] - v[j][1]) * ny + (v[i][2] - v[j][2]) * nz;
  double meff = rmass[i] * rmass[j] / (rmass[i] + rmass[j]);
  if (mask[i] & freeze_group_bit) meff = rmass[j];
  if (mask[j] & freeze_group_bit) meff = rmass[i];
  const double Reff = radius[i] * radius[j] / radsum;
  const granular::NormalForce nf = granular::normal_force(at(itype, jtype), radsum - r, Reff, meff, vnnr);
  fforce = nf.force * rinv;
  return 0.0;
}

double PairGranularRollslide::memory_usage()
{
  const double common = 3 * sizeof(double) + sizeof(uint32_t) + sizeof(Pending);
  return (double) CHUNK * (2 * common + 2 * sizeof(uint32_t) + sizeof(size_t) +
                           sizeof(rsl_contact_state) + 2 * sizeof(rsl_sphere) +
                           sizeof(rsl_batch_loads)) +
      (double) spheres.capacity() * sizeof(rsl_sphere) +
      (double) (direct.energy.capacity() + paired.energy.capacity()) *
          (sizeof(rsl_contact_energy) + 2 * sizeof(double)) +
      (double) contact_rates.capacity() * sizeof(double) +
      (double) rates_pass.capacity() * sizeof(unsigned) + (double) list_index.capacity() * sizeof(int);
}
