// fix rollslide/history: see fix_rollslide_history.h. Created by pair_style
// granular/rollslide (ID ROLLSLIDE_HISTORY), never by the user.
//
// Two homes for the history, one current at a time (`live`):
// - per neighbour-list entry (`state[first[ii] + jj]`, the list atom i as body 1), what the pair
//   style steps, valid from a neighbour-list build to the next pre_exchange;
// - per owned atom (`partners[i]`: partner ID + state with atom i as body 1), what migrates
//   with the atoms (pack/unpack_exchange), is sorted with them (copy_arrays) and goes into
//   restart files (pack/unpack_restart), valid from pre_exchange (or post_run) to the next build.
// pre_exchange moves entries to atoms: a contact of two owned atoms is stored on both, the
// second copy mirrored with rsl_contact_state_swap (the partner as body 1); a contact with a
// ghost atom is stored on the owned atom only, because the pair style's newton off list makes
// the ghost's own rank compute (and store) the same contact from its side. post_neighbor moves
// them back, looking each neighbour's ID up in the list atom's partners.
//
// With energy tracking (a compute needs the contacts' energy: PairGranularRollslide::
// tracks_energy) each entry also has the elastic energy of its contact's springs after its
// last step (`elastic`), which goes with the state (the same from either side: energies do not
// change when the bodies swap) into `partner_elastic`, the exchange and restart files; without
// it, the records are those of before (restart files of either kind are read).
#include "fix_rollslide_history.h"

#include "pair_granular_rollslide.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "neigh_list.h"
#include "update.h"

#include <algorithm>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

static_assert(sizeof(rsl_contact_state) == 13 * sizeof(double) + 2 * sizeof(uint32_t),
              "rsl_contact_state: 13 doubles and two 32-bit integers");

FixRollslideHistory::FixRollslideHistory(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  if (narg != 3) error->all(FLERR, std::string("fix rollslide/history takes no arguments"));
  restart_global = 1;    // write_restart() is the hook that makes the per-atom lists current
  restart_peratom = 1;
  create_attribute = 1;
  maxexchange_dynamic = 1;
  maxexchange = 1;
  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);
}

FixRollslideHistory::~FixRollslideHistory()
{
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
}

int FixRollslideHistory::setmask()
{
  return PRE_EXCHANGE | POST_NEIGHBOR;
}

void FixRollslideHistory::init()
{
  if (pair == nullptr || force->pair != static_cast<Pair *>(pair))
    error->all(FLERR, std::string("fix rollslide/history belongs to pair_style granular/rollslide, "
                                  "which is not the pair style (pair_style hybrid is not supported)"));
}

void FixRollslideHistory::pack_partner(const Partner &p, double *buf)
{
  const rsl_contact_state &s = p.state;
  const double values[PARTNER_DOUBLES] = {(double) p.tag,
                                          s.sliding_spring.x, s.sliding_spring.y, s.sliding_spring.z,
                                          s.rolling_spring.x, s.rolling_spring.y, s.rolling_spring.z,
                                          s.twisting_angle,
                                          s.model_memory.x, s.model_memory.y, s.model_memory.z,
                                          s.previous_normal.x, s.previous_normal.y, s.previous_normal.z,
                                          (double) s.slip_flags};
  memcpy(buf, values, sizeof values);
}

void FixRollslideHistory::unpack_partner(const double *b, Partner &p)
{
  p.tag = (tagint) b[0];
  rsl_contact_state &s = p.state;
  s.sliding_spring = {b[1], b[2], b[3]};
  s.rolling_spring = {b[4], b[5], b[6]};
  s.twisting_angle = b[7];
  s.model_memory = {b[8], b[9], b[10]};
  s.previous_normal = {b[11], b[12], b[13]};
  s.slip_flags = (uint32_t) b[14];
  s.reserved = 0;
}

// Entries -> atoms (see the file comment). Only when the entries are the current copy.
void FixRollslideHistory::to_atoms()
{
  if (!live) return;
  NeighList *list = pair->list;
  const int nlocal = atom->nlocal;
  tagint *tag = atom->tag;
  int *type = atom->type;
  const bool energy = !state.empty() && elastic.size() == ENERGIES * state.size();
  for (int i = 0; i < nlocal; i++) {
    partners[i].clear();
    partner_elastic[i].clear();
  }
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    const int *jlist = list->firstneigh[i];
    const bigint base = first[ii];
    for (int jj = 0; jj < list->numneigh[i]; jj++) {
      const bigint e = base + jj;
      if (!touch[e]) continue;
      const int j = jlist[jj] & NEIGHMASK;
      partners[i].push_back({tag[j], state[e]});
      std::array<double, ENERGIES> energies{};
      if (energy) {
        for (int c = 0; c < ENERGIES; c++) energies[c] = elastic[ENERGIES * e + c];
        partner_elastic[i].push_back(energies);
      }
      if (j < nlocal) {
        Partner mirrored{tag[i], state[e]};
        int32_t st = rsl_contact_state_swap(pair->model(type[j], type[i]), &mirrored.state);
        if (st != RSL_OK) pair->library_error("rsl_contact_state_swap", st, tag[j], tag[i]);
        partners[j].push_back(mirrored);
        if (energy) partner_elastic[j].push_back(energies);
      }
    }
  }
  live = false;
  update_maxexchange();
}

// Atoms -> entries, for the current neighbour list.
void FixRollslideHistory::build_entries()
{
  NeighList *list = pair->list;
  tagint *tag = atom->tag;
  const int inum = list->inum;
  first.resize(inum + 1);
  bigint total = 0;
  for (int ii = 0; ii < inum; ii++) {
    first[ii] = total;
    total += list->numneigh[list->ilist[ii]];
  }
  first[inum] = total;
  touch.assign(total, 0);
  state.resize(total);
  rsl_contact_state fresh;
  memset(&fresh, 0, sizeof fresh);
  std::fill(state.begin(), state.end(), fresh);
  const bool energy = pair->tracks_energy();
  elastic.assign(energy ? ENERGIES * total : 0, 0.0);
  for (int ii = 0; ii < inum; ii++) {
    const int i = list->ilist[ii];
    const std::vector<Partner> &mine = partners[i];
    if (mine.empty()) continue;
    const bool energies = energy && partner_elastic[i].size() == mine.size();
    const int *jlist = list->firstneigh[i];
    for (int jj = 0; jj < list->numneigh[i]; jj++) {
      const tagint want = tag[jlist[jj] & NEIGHMASK];
      for (size_t k = 0; k < mine.size(); k++)
        if (mine[k].tag == want) {
          const bigint e = first[ii] + jj;
          state[e] = mine[k].state;
          touch[e] = 1;
          if (energies)
            for (int c = 0; c < ENERGIES; c++) elastic[ENERGIES * e + c] = partner_elastic[i][k][c];
          break;
        }
    }
  }
  live = true;
}

void FixRollslideHistory::update_maxexchange()
{
  size_t most = 0;
  for (int i = 0; i < atom->nlocal; i++)
    if (partners[i].size() > most) most = partners[i].size();
  maxexchange = 2 + (PARTNER_DOUBLES + ENERGY_DOUBLES) * static_cast<int>(most);
}

void FixRollslideHistory::pre_exchange()
{
  to_atoms();
}

void FixRollslideHistory::setup_post_neighbor()
{
  post_neighbor();
}

void FixRollslideHistory::post_neighbor()
{
  // A build not preceded by pre_exchange (atoms not renumbered since the entries were made).
  to_atoms();
  build_entries();
}

// Called by Modify for every fix at the end of a run: between runs the per-atom lists are the
// current copy (atoms may be added, deleted, written to a restart file).
void FixRollslideHistory::post_run()
{
  to_atoms();
}

void FixRollslideHistory::write_restart(FILE *fp)
{
  to_atoms();
  if (comm->me == 0) {
    int size = 0;
    fwrite(&size, sizeof(int), 1, fp);
  }
}

double FixRollslideHistory::memory_usage()
{
  double bytes = (double) partners.capacity() * sizeof(std::vector<Partner>);
  for (const auto &p : partners) bytes += (double) p.capacity() * sizeof(Partner);
  bytes += (double) partner_elastic.capacity() * sizeof(partner_elastic[0]) +
      (double) elastic.capacity() * sizeof(double);
  for (const auto &p : partner_elastic) bytes += (double) p.capacity() * sizeof(p[0]);
  bytes += (double) state.capacity() * sizeof(rsl_contact_state) + touch.capacity() +
      (double) first.capacity() * sizeof(bigint);
  return bytes;
}

void FixRollslideHistory::grow_arrays(int nmax)
{
  if ((int) partners.size() < nmax) {
    partners.resize(nmax);
    partner_elastic.resize(nmax);
  }
}

void FixRollslideHistory::copy_arrays(int i, int j, int)
{
  partners[j] = partners[i];
  partner_elastic[j] = partner_elastic[i];
}

void FixRollslideHistory::set_arrays(int i)
{
  partners[i].clear();
  partner_elastic[i].clear();
}

// Atom i's partners as records of record_doubles(i) doubles (pack_partner's, then the
// energies if it has them); returns the doubles written.
int FixRollslideHistory::pack_partners(int i, double *buf) const
{
  const bool energies = !partner_elastic[i].empty();
  int m = 0;
  for (size_t k = 0; k < partners[i].size(); k++) {
    pack_partner(partners[i][k], &buf[m]);
    m += PARTNER_DOUBLES;
    if (energies)
      for (int c = 0; c < ENERGY_DOUBLES; c++) buf[m++] = partner_elastic[i][k][c];
  }
  return m;
}

// Reads n records of `per` doubles (PARTNER_DOUBLES, or with the energies) into atom i's lists;
// returns the doubles read.
int FixRollslideHistory::unpack_partners(int i, const double *buf, int n, int per)
{
  partners[i].resize(n);
  partner_elastic[i].clear();
  const int nenergies = per - PARTNER_DOUBLES;    // ENERGY_DOUBLES, OLD_ENERGY_DOUBLES or 0
  const bool energies = nenergies > 0;
  if (energies) partner_elastic[i].assign(n, std::array<double, ENERGIES>{});
  int m = 0;
  for (int k = 0; k < n; k++) {
    unpack_partner(&buf[m], partners[i][k]);
    if (energies)
      for (int c = 0; c < nenergies; c++) partner_elastic[i][k][c] = buf[m + PARTNER_DOUBLES + c];
    m += per;
  }
  // This rank may send the atom on before its next pre_exchange: Comm sizes its buffers from
  // maxexchange, which must cover every owned atom's list.
  if (2 + per * n > maxexchange) maxexchange = 2 + per * n;
  return m;
}

int FixRollslideHistory::pack_exchange(int i, double *buf)
{
  buf[0] = (double) partners[i].size();
  buf[1] = (double) record_doubles(i);
  return 2 + pack_partners(i, &buf[2]);
}

int FixRollslideHistory::unpack_exchange(int nlocal, double *buf)
{
  grow_arrays(nlocal + 1);
  return 2 + unpack_partners(nlocal, &buf[2], (int) buf[0], (int) buf[1]);
}

int FixRollslideHistory::pack_restart(int i, double *buf)
{
  // buf[0] is the length of this fix's values, read by Atom to skip them (and here to tell
  // the records with energies from those without).
  buf[1] = (double) partners[i].size();
  const int m = 2 + pack_partners(i, &buf[2]);
  buf[0] = m;
  return m;
}

void FixRollslideHistory::unpack_restart(int nlocal, int nth)
{
  grow_arrays(nlocal + 1);
  double **extra = atom->extra;
  int m = 0;
  for (int k = 0; k < nth; k++) m += static_cast<int>(extra[nlocal][m]);
  const int length = static_cast<int>(extra[nlocal][m]);
  const int n = static_cast<int>(extra[nlocal][m + 1]);
  const int per = n > 0 ? (length - 2) / n : PARTNER_DOUBLES;
  if (n > 0 && (length - 2 != per * n || (per != PARTNER_DOUBLES && per != PARTNER_DOUBLES + ENERGY_DOUBLES &&
                              per != PARTNER_DOUBLES + OLD_ENERGY_DOUBLES)))
    error->one(FLERR, std::string("fix rollslide/history: unknown restart record (") +
                          std::to_string(length) + " values for " + std::to_string(n) + " contacts)");
  unpack_partners(nlocal, &extra[nlocal][m + 2], n, per);
  live = false;
}

int FixRollslideHistory::size_restart(int nlocal)
{
  return 2 + record_doubles(nlocal) * (int) partners[nlocal].size();
}

int FixRollslideHistory::maxsize_restart()
{
  int most = 2;
  for (int i = 0; i < atom->nlocal; i++) most = std::max(most, size_restart(i));
  int all = 0;
  MPI_Allreduce(&most, &all, 1, MPI_INT, MPI_MAX, world);
  return all;
}
