// compute rollslide/energy: see compute_rollslide_energy.h.
//
// The cumulative per-atom columns (dissipation, transport, stiffness change) live in an
// internal fix (class Store below, style `rollslide/energy/store`, ID
// `ROLLSLIDE_ENERGY_<compute ID>`, group all) that the compute creates in its constructor and
// deletes in its destructor. The fix moves the columns with
// their atoms (exchange between ranks, atom sorting) and writes them into restart files
// (restart_peratom). After read_restart, LAMMPS keeps every fix's per-atom restart values by
// fix ID and style until the first run; a fix created before then with the same ID and style
// gets its values back, atom by atom (Modify::add_fix calls its unpack_restart). Since the
// fix's ID is derived from the compute's, redefining the compute with the same ID after
// read_restart carries the cumulative columns on. The elastic columns ("now") are the
// compute's own, zeroed at the start of each contact pass and filled by it: nothing moves the
// atoms between a pass and the outputs of its step.
//
// The fix also marks where a contact pass starts: its pre_force (every step) and
// setup_pre_force (a run's setup) run after the atoms have moved and before the pair style's
// force computation and the wall fixes' post_force, so the first producer's begin_step after
// either starts a new pass.
#include "compute_rollslide_energy.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "fix.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "pair.h"
#include "update.h"

#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {
constexpr int NDISSIPATION = ComputeRollslideEnergy::WALL_TWISTING_FRICTION + 1;
constexpr int NCOLUMNS = ComputeRollslideEnergy::NCOLUMNS;
constexpr int NSLOTS = ComputeRollslideEnergy::NSLOTS;
// The slots sent with an atom and written to restart files: all of them (the stiffness change
// and the neck breaking last; restart files written before them have the 15 or 16 before
// them, and are read as such, the later slots starting from zero).
constexpr int NSTORED = ComputeRollslideEnergy::NCUMULATIVE;
static_assert(ComputeRollslideEnergy::slot(ComputeRollslideEnergy::TRANSPORT) == 7 &&
                  ComputeRollslideEnergy::slot(ComputeRollslideEnergy::WALL_TWISTING_FRICTION) == 14 &&
                  ComputeRollslideEnergy::slot(ComputeRollslideEnergy::STIFFNESS_CHANGE) == 15 &&
                  ComputeRollslideEnergy::slot(ComputeRollslideEnergy::PAIR_NECK_BREAKING) == 16 &&
                  ComputeRollslideEnergy::slot(ComputeRollslideEnergy::WALL_NECK_BREAKING) == 17 &&
                  NSTORED == NSLOTS,
              "slot layout");
constexpr int NELASTIC = ComputeRollslideEnergy::NELASTIC;
}    // namespace

class ComputeRollslideEnergy::Store : public Fix {
 public:
  static constexpr const char *STYLE = "rollslide/energy/store";
  // The compute creating the fix (set around its add_fix): the fix refuses to be made by hand.
  static ComputeRollslideEnergy *creating;

  Store(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
  {
    if (creating == nullptr)
      error->all(FLERR, std::string("fix ") + STYLE + " is internal to compute " +
                            ComputeRollslideEnergy::STYLE + " and cannot be defined");
    compute = creating;
    compute->store = this;
    restart_peratom = 1;
    create_attribute = 1;
    maxexchange = NSTORED;
    grow_arrays(atom->nmax);
    atom->add_callback(Atom::GROW);
    atom->add_callback(Atom::RESTART);
  }

  ~Store() override
  {
    atom->delete_callback(id, Atom::GROW);
    atom->delete_callback(id, Atom::RESTART);
    memory->destroy(values);
  }

  int setmask() override { return PRE_FORCE; }
  void setup_pre_force(int) override { compute->new_pass = true; }
  void pre_force(int) override { compute->new_pass = true; }

  double memory_usage() override { return (double) nmax * NSLOTS * sizeof(double); }

  void grow_arrays(int n) override
  {
    if (n <= nmax) return;
    memory->grow(values, n, NSLOTS, "rollslide/energy:values");
    // Rows are set before an atom uses them (set_arrays, copy_arrays, unpack_*); zeroed here
    // too, for atoms a command makes without telling the fixes.
    for (int i = nmax; i < n; i++) memset(values[i], 0, NSLOTS * sizeof(double));
    nmax = n;
    compute->cumulative = values;
  }
  void copy_arrays(int i, int j, int) override { memcpy(values[j], values[i], NSTORED * sizeof(double)); }
  void set_arrays(int i) override { memset(values[i], 0, NSTORED * sizeof(double)); }
  int pack_exchange(int i, double *buf) override
  {
    memcpy(buf, values[i], NSTORED * sizeof(double));
    return NSTORED;
  }
  int unpack_exchange(int nlocal, double *buf) override
  {
    grow_arrays(nlocal + 1);
    memcpy(values[nlocal], buf, NSTORED * sizeof(double));
    return NSTORED;
  }
  int pack_restart(int i, double *buf) override
  {
    // buf[0]: the length of this fix's values, which Atom reads to skip over them.
    buf[0] = NSTORED + 1;
    memcpy(&buf[1], values[i], NSTORED * sizeof(double));
    return NSTORED + 1;
  }
  void unpack_restart(int nlocal, int nth) override
  {
    grow_arrays(nlocal + 1);
    double *extra = atom->extra[nlocal];
    int m = 0;
    for (int k = 0; k < nth; k++) m += static_cast<int>(extra[m]);
    // A restart file written before the stiffness change or the neck breaking columns has the
    // slots before them only: those start from zero.
    const int stored = static_cast<int>(extra[m]) - 1;
    const int n = stored < NSTORED ? stored : NSTORED;
    memset(values[nlocal], 0, NSTORED * sizeof(double));
    memcpy(values[nlocal], &extra[m + 1], n * sizeof(double));
  }
  int size_restart(int) override { return NSTORED + 1; }
  int maxsize_restart() override { return NSTORED + 1; }

  ComputeRollslideEnergy *compute = nullptr;
  double **values = nullptr;    // per atom, NSLOTS (ComputeRollslideEnergy::slot)
  int nmax = 0;
};

ComputeRollslideEnergy *ComputeRollslideEnergy::Store::creating = nullptr;

namespace {
Fix *create_store(LAMMPS *lmp, int narg, char **arg)
{
  return new ComputeRollslideEnergy::Store(lmp, narg, arg);
}
}    // namespace

ComputeRollslideEnergy::ComputeRollslideEnergy(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg)
{
  if (narg != 3)
    error->all(FLERR, std::string("compute ") + STYLE + " takes no arguments: compute ID group " + STYLE);
  vector_flag = 1;
  size_vector = NVECTOR;
  extvector = 1;    // energies and energy rates: summed over atoms (thermo_modify norm divides)
  peratom_flag = 1;
  size_peratom_cols = NCOLUMNS;
  memset(values, 0, sizeof values);
  vector = values;
  clear_pass();

  (*modify->fix_map)[Store::STYLE] = &create_store;
  store_id = std::string("ROLLSLIDE_ENERGY_") + id;
  Store::creating = this;
  store = static_cast<Store *>(modify->add_fix(store_id + " all " + Store::STYLE));
  Store::creating = nullptr;
}

ComputeRollslideEnergy::~ComputeRollslideEnergy()
{
  memory->destroy(peratom);
  // LAMMPS deletes its fixes before its computes when it ends; the store may be gone already.
  if (modify->find_fix(store_id) >= 0) modify->delete_fix(store_id);
}

void ComputeRollslideEnergy::init()
{
  for (int i = 0; i < modify->ncompute; i++)
    if (strcmp(modify->compute[i]->style, STYLE) == 0) {
      if (modify->compute[i] != this)
        error->all(FLERR, std::string("compute ") + STYLE + " " + id +
                              ": only one compute of this style can be defined (the first, " +
                              modify->compute[i]->id + ", receives the contacts)");
      break;
    }
  const int ifix = modify->find_fix(store_id);
  if (ifix < 0) error->all(FLERR, std::string("compute ") + STYLE + " " + id + ": its fix " + store_id + " was deleted");
  store = static_cast<Store *>(modify->fix[ifix]);
  cumulative = store->values;
  bool producer = force->pair_match("granular/rollslide", 1) != nullptr;
  for (int i = 0; i < modify->nfix && !producer; i++)
    producer = strcmp(modify->fix[i]->style, "wall/gran/rollslide") == 0;
  if (!producer && comm->me == 0)
    error->warning(FLERR, std::string("compute ") + STYLE + " " + id +
                              ": neither pair_style granular/rollslide nor a fix wall/gran/rollslide "
                              "is defined: nothing will be tallied");
}

void ComputeRollslideEnergy::clear_pass()
{
  memset(pass, 0, sizeof pass);
  pass_dt = update->dt;
}

void ComputeRollslideEnergy::begin_step()
{
  if (!new_pass) return;
  new_pass = false;
  clear_pass();
  elastic.assign((size_t) NELASTIC * atom->nlocal, 0.0);
}

void ComputeRollslideEnergy::compute_vector()
{
  invoked_vector = update->ntimestep;
  // This rank's column sums, then its last pass's dissipation; summed over the ranks at once.
  double local[NCOLUMNS + NDISSIPATION + 2], all[NCOLUMNS + NDISSIPATION + 2];
  memset(local, 0, sizeof local);
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++)
    for (int c = 0; c < NCOLUMNS; c++)
      if (cumulative_column(c)) local[c] += cumulative[i][slot(c)];
  // The elastic columns of the last pass (none if the atoms changed since: no pass yet).
  if (elastic.size() == (size_t) NELASTIC * nlocal)
    for (int i = 0; i < nlocal; i++)
      for (int c = 0; c < NELASTIC; c++) local[ELASTIC_NORMAL + c] += elastic[NELASTIC * i + c];
  for (int c = 0; c < NDISSIPATION; c++) local[NCOLUMNS + c] = pass[slot(c)];
  local[NCOLUMNS + NDISSIPATION] = pass[PAIR_NECK_SLOT];
  local[NCOLUMNS + NDISSIPATION + 1] = pass[WALL_NECK_SLOT];
  MPI_Allreduce(local, all, NCOLUMNS + NDISSIPATION + 2, MPI_DOUBLE, MPI_SUM, world);

  for (int c = 0; c < NCOLUMNS; c++) values[vector_index(c)] = all[c];
  double dissipated = 0.0, rate = 0.0;
  for (int c = 0; c < NDISSIPATION; c++) {
    dissipated += all[c];
    values[RATE_FIRST + c] = all[NCOLUMNS + c] / pass_dt;
    rate += values[RATE_FIRST + c];
  }
  // The necks broken (and in the last pass: the rate).
  dissipated += all[PAIR_NECK_BREAKING] + all[WALL_NECK_BREAKING];
  rate += (all[NCOLUMNS + NDISSIPATION] + all[NCOLUMNS + NDISSIPATION + 1]) / pass_dt;
  values[TOTAL_DISSIPATED] = dissipated;
  values[TOTAL_ELASTIC] = all[ELASTIC_NORMAL] + all[ELASTIC_SLIDING] + all[ELASTIC_ROLLING] + all[ELASTIC_TWISTING];
  values[RATE] = rate;
}

void ComputeRollslideEnergy::compute_peratom()
{
  invoked_peratom = update->ntimestep;
  if (atom->nmax > nmax_peratom) {
    nmax_peratom = atom->nmax;
    memory->destroy(peratom);
    memory->create(peratom, nmax_peratom, NCOLUMNS, "rollslide/energy:peratom");
  }
  const int nlocal = atom->nlocal;
  const bool now = elastic.size() == (size_t) NELASTIC * nlocal;
  for (int i = 0; i < nlocal; i++) {
    for (int c = 0; c < NCOLUMNS; c++)
      if (cumulative_column(c)) peratom[i][c] = cumulative[i][slot(c)];
    for (int c = 0; c < NELASTIC; c++) peratom[i][ELASTIC_NORMAL + c] = now ? elastic[NELASTIC * i + c] : 0.0;
  }
  array_atom = peratom;
}

double ComputeRollslideEnergy::memory_usage()
{
  // The cumulative columns are the store's (counted by the fix).
  return (double) nmax_peratom * NCOLUMNS * sizeof(double) + (double) elastic.capacity() * sizeof(double);
}
