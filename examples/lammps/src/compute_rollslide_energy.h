// compute ID group rollslide/energy
//
// Where the energy of the rollslide contacts goes, by mechanism: what the contacts of
// pair_style granular/rollslide and of fix wall/gran/rollslide dissipated since the compute was
// defined (carried through restart files), the elastic energy their springs hold now, and
// what the springs' transport and their changes of stiffness added to it; the energy JKR necks
// lost when they broke.
//
// The producers (the pair style and every rollslide wall fix) find this compute in their init
// (the first compute of this style), make their library models track energy, and report every
// stepped contact through `tally` once per step, after calling `begin_step`.
#ifndef ROLLSLIDE_COMPUTE_ROLLSLIDE_ENERGY_H
#define ROLLSLIDE_COMPUTE_ROLLSLIDE_ENERGY_H

#include "atom.h"
#include "compute.h"
#include "rollslide.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class ComputeRollslideEnergy : public Compute {
 public:
  static constexpr const char *STYLE = "rollslide/energy";

  // The columns of the per-atom array, in this order (energy units); the global vector holds
  // their sums over all atoms (`vector_index`): the columns before STIFFNESS_CHANGE, then the
  // extra entries (Extra), then STIFFNESS_CHANGE's and the neck-breaking columns' (appended last
  // in both, so that the older columns kept their numbers).
  enum Column {
    // Dissipated since the compute was defined, by contacts between two particles.
    PAIR_NORMAL_DAMPING,
    PAIR_SLIDING_DASHPOT,
    PAIR_SLIDING_FRICTION,
    PAIR_ROLLING_DASHPOT,
    PAIR_ROLLING_FRICTION,
    PAIR_TWISTING_DASHPOT,
    PAIR_TWISTING_FRICTION,
    // The same for contacts with a rollslide wall.
    WALL_NORMAL_DAMPING,
    WALL_SLIDING_DASHPOT,
    WALL_SLIDING_FRICTION,
    WALL_ROLLING_DASHPOT,
    WALL_ROLLING_FRICTION,
    WALL_TWISTING_DASHPOT,
    WALL_TWISTING_FRICTION,
    // Change of the springs' elastic energy by their transport (rsl_contact_energy.transport),
    // summed since the compute was defined (0 to rounding for exact transports).
    TRANSPORT,
    // Elastic energy held now (pair and wall contacts).
    ELASTIC_NORMAL,
    ELASTIC_SLIDING,
    ELASTIC_ROLLING,
    ELASTIC_TWISTING,
    // Change of the springs' elastic energy by their changes of stiffness with no work done
    // (rsl_contact_energy.stiffness_change: Mindlin's k_t = kt a and Marshall's twisting
    // stiffness follow the contact radius), summed since the compute was defined, pair and
    // wall contacts. A closed system's budget subtracts it as it does TRANSPORT.
    STIFFNESS_CHANGE,
    // Dissipated since the compute was defined by JKR necks breaking at pull-off: the normal
    // force's potential a neck held when it broke (U(a) of its last step, counted from the
    // touch), by contacts between two particles, and by contacts with a rollslide wall.
    PAIR_NECK_BREAKING,
    WALL_NECK_BREAKING,
    NCOLUMNS
  };

  ComputeRollslideEnergy(class LAMMPS *, int, char **);
  ~ComputeRollslideEnergy() override;
  void init() override;
  void compute_vector() override;
  void compute_peratom() override;
  double memory_usage() override;

  // Called by each producer at the start of its contact pass; the first call of a timestep
  // clears this step's elastic columns and dissipation rate (later calls of the same timestep
  // do nothing). "Timestep" here is one force computation: each step's, and a run's setup
  // pass (which may repeat the timestep of the previous run's last step).
  void begin_step();
  // One contact's step, as reported by its producer for its local atom `i` (i < nlocal):
  // `share` of the contact's energy goes to atom i (1 for a wall contact, 1/2 for a contact
  // between two particles: the other half goes to the partner, tallied by whichever rank
  // owns it), `wall` says which dissipation columns take it; `energy` is the library's split
  // of the step, `normal_dissipated` the energy the normal dashpot dissipated this step
  // (>= 0) and `normal_elastic` the normal spring's energy after the step (both computed by
  // the producer, which computes the normal force).
  //
  // A contact that ends (the producer drops its history) takes its springs' elastic energy
  // with it: the producer reports it once more, in the pass where it finds the contact
  // ended, as dissipated by the sliders (`energy` all zero but slider_sliding, slider_rolling,
  // slider_twisting = the elastic_sliding, elastic_rolling, elastic_twisting of the contact's
  // last step; normal terms 0). Without that, the budget misses the energy springs held when
  // their contacts opened (with the dashpots of LAMMPS' clip rule, O(gamma^2 v^2 / k) per
  // contact, which does not fall with dt).
  //
  // Inline: a producer calls it once or twice per contact and step.
  void tally(int i, double share, bool wall, const rsl_contact_energy &energy,
             double normal_dissipated, double normal_elastic)
  {
    if (!(atom->mask[i] & groupbit)) return;
    double *c = cumulative[i];
    double *d = pass;
    if (wall) {
      c += WALL_SLOT;
      d += WALL_SLOT;
    }
    const double x[7] = {share * normal_dissipated,   share * energy.dashpot_sliding,
                         share * energy.slider_sliding,  share * energy.dashpot_rolling,
                         share * energy.slider_rolling,  share * energy.dashpot_twisting,
                         share * energy.slider_twisting};
    for (int k = 0; k < 7; k++) {
      c[k] += x[k];
      d[k] += x[k];
    }
    const double t = share * energy.transport;
    cumulative[i][TRANSPORT_SLOT] += t;
    pass[TRANSPORT_SLOT] += t;
    const double stiffness = share * energy.stiffness_change;
    cumulative[i][STIFFNESS_SLOT] += stiffness;
    pass[STIFFNESS_SLOT] += stiffness;
    double *e = &elastic[NELASTIC * i];
    e[0] += share * normal_elastic;
    e[1] += share * energy.elastic_sliding;
    e[2] += share * energy.elastic_rolling;
    e[3] += share * energy.elastic_twisting;
  }

  // A JKR neck between atom i and atom j broke, losing the energy `neck` (its normal force's
  // potential): half to i, half to j if local (the pair style; a ghost j's owner tallies its
  // half), in PAIR_NECK_BREAKING.
  void tally_neck_pair(int i, int j, int nlocal, double neck)
  {
    const int *mask = atom->mask;
    if (mask[i] & groupbit) {
      cumulative[i][PAIR_NECK_SLOT] += 0.5 * neck;
      pass[PAIR_NECK_SLOT] += 0.5 * neck;
    }
    if (j < nlocal && (mask[j] & groupbit)) {
      cumulative[j][PAIR_NECK_SLOT] += 0.5 * neck;
      pass[PAIR_NECK_SLOT] += 0.5 * neck;
    }
  }
  // Atom i's JKR neck with a wall broke, losing `neck`: WALL_NECK_BREAKING.
  void tally_neck_wall(int i, double neck)
  {
    if (!(atom->mask[i] & groupbit)) return;
    cumulative[i][WALL_NECK_SLOT] += neck;
    pass[WALL_NECK_SLOT] += neck;
  }

  // tally(i, 1/2, false, ...) and, if j < nlocal, tally(j, 1/2, false, ...) in one call (the
  // pair style's: it keeps the contact's terms in registers once for both atoms and adds this
  // pass's totals once).
  void tally_pair(int i, int j, int nlocal, const rsl_contact_energy &energy,
                  double normal_dissipated, double normal_elastic)
  {
    const int *mask = atom->mask;
    const bool take_i = mask[i] & groupbit, take_j = j < nlocal && (mask[j] & groupbit);
    if (!take_i && !take_j) return;
    const double x[WALL_SLOT] = {
        0.5 * normal_dissipated,      0.5 * energy.dashpot_sliding, 0.5 * energy.slider_sliding,
        0.5 * energy.dashpot_rolling, 0.5 * energy.slider_rolling,  0.5 * energy.dashpot_twisting,
        0.5 * energy.slider_twisting, 0.5 * energy.transport};
    const double el[NELASTIC] = {0.5 * normal_elastic, 0.5 * energy.elastic_sliding,
                                 0.5 * energy.elastic_rolling, 0.5 * energy.elastic_twisting};
    const double stiffness = 0.5 * energy.stiffness_change;
    double **cum = cumulative;
    double *now = elastic.data();
    for (int a = 0; a < 2; a++) {
      if (!(a == 0 ? take_i : take_j)) continue;
      const int atom_index = a == 0 ? i : j;
      double *c = cum[atom_index];
      for (int k = 0; k < WALL_SLOT; k++) c[k] += x[k];    // the 7 pair columns, transport
      // (Another cache line of the row: left alone by the laws whose stiffness is constant.)
      if (stiffness != 0.0) c[STIFFNESS_SLOT] += stiffness;
      double *e = now + NELASTIC * atom_index;
      for (int k = 0; k < NELASTIC; k++) e[k] += el[k];
    }
    const double w = (take_i ? 1.0 : 0.0) + (take_j ? 1.0 : 0.0);
    for (int k = 0; k < WALL_SLOT; k++) pass[k] += w * x[k];
    pass[STIFFNESS_SLOT] += w * stiffness;
  }

  // The global vector: the sums of the columns before STIFFNESS_CHANGE, then these entries
  // (energy, energy/time), then the sums of STIFFNESS_CHANGE, PAIR_NECK_BREAKING and
  // WALL_NECK_BREAKING (appended in that order, so that the older entries kept their numbers).
  enum Extra {
    TOTAL_DISSIPATED = STIFFNESS_CHANGE,    // the 16 dissipation columns summed (necks included)
    TOTAL_ELASTIC,                          // the 4 elastic columns summed
    RATE,                                   // total dissipation rate of the last contact pass
    RATE_FIRST,    // then each of the 14 first dissipation columns' rate, in column order
    STIFFNESS_CHANGE_SUM = RATE_FIRST + WALL_TWISTING_FRICTION + 1,
    PAIR_NECK_BREAKING_SUM,
    WALL_NECK_BREAKING_SUM,
    NVECTOR
  };
  // A column's entry in the global vector.
  static constexpr int vector_index(int column)
  {
    return column == STIFFNESS_CHANGE     ? STIFFNESS_CHANGE_SUM
        : column == PAIR_NECK_BREAKING    ? PAIR_NECK_BREAKING_SUM
        : column == WALL_NECK_BREAKING    ? WALL_NECK_BREAKING_SUM
                                          : column;
  }
  // The cumulative columns (dissipation, transport, stiffness change, neck breaking), kept by
  // the store, and the elastic ones, kept by the compute for the current pass.
  static constexpr bool cumulative_column(int column)
  {
    return column <= TRANSPORT || column >= STIFFNESS_CHANGE;
  }
  static constexpr int NCUMULATIVE = TRANSPORT + 4;
  static constexpr int NELASTIC = ELASTIC_TWISTING + 1 - ELASTIC_NORMAL;
  // The store's row of an atom holds the cumulative columns in slots: the 8 a contact between
  // particles adds to (its 7 dissipation columns, then TRANSPORT) first, in one 64-byte cache
  // line, then the wall's 7, then STIFFNESS_CHANGE (which only the mindlin family and Marshall's
  // twisting change).
  static constexpr int TRANSPORT_SLOT = PAIR_TWISTING_FRICTION + 1, WALL_SLOT = TRANSPORT_SLOT + 1;
  static constexpr int STIFFNESS_SLOT = WALL_SLOT + 7;
  static constexpr int PAIR_NECK_SLOT = STIFFNESS_SLOT + 1, WALL_NECK_SLOT = STIFFNESS_SLOT + 2;
  static constexpr int NSLOTS = 18;
  static constexpr int slot(int column)
  {
    return column < WALL_NORMAL_DAMPING   ? column
        : column < TRANSPORT              ? column + 1
        : column == TRANSPORT             ? TRANSPORT_SLOT
        : column == STIFFNESS_CHANGE      ? STIFFNESS_SLOT
        : column == PAIR_NECK_BREAKING    ? PAIR_NECK_SLOT
                                          : WALL_NECK_SLOT;
  }

  // The fix holding the cumulative per-atom columns (internal; created and deleted by the
  // compute).
  class Store;

 private:
  Store *store = nullptr;
  std::string store_id;
  double **cumulative = nullptr;    // the store's rows, per atom (NSLOTS)
  std::vector<double> elastic;      // NELASTIC per local atom, this pass
  double **peratom = nullptr;       // the per-atom array (output)
  int nmax_peratom = 0;
  bool new_pass = true;      // the next begin_step starts a contact pass (set by the store)
  double pass_dt = 0.0;      // the time step of the last pass
  double pass[NSLOTS];       // this rank's cumulative terms in the last pass, by slot
  double values[NVECTOR];    // the global vector
  void clear_pass();
};

}    // namespace LAMMPS_NS

#endif
