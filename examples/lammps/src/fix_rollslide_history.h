// The contact history of pair_style granular/rollslide: one rsl_contact_state per touching
// contact, kept per neighbour-list entry while a list lives, and per atom (keyed by the
// partner's atom ID, in that atom's own perspective: the atom is body 1) across neighbour
// list rebuilds, migration between MPI ranks and restart files.
#ifndef ROLLSLIDE_FIX_ROLLSLIDE_HISTORY_H
#define ROLLSLIDE_FIX_ROLLSLIDE_HISTORY_H

#include "fix.h"
#include "rollslide.h"

#include <array>
#include <vector>

namespace LAMMPS_NS {

class PairGranularRollslide;

class FixRollslideHistory : public Fix {
 public:
  static constexpr const char *STYLE = "rollslide/history";
  static constexpr const char *ID = "ROLLSLIDE_HISTORY";

  FixRollslideHistory(class LAMMPS *, int, char **);
  ~FixRollslideHistory() override;
  int setmask() override;
  void init() override;
  void setup_post_neighbor() override;
  void pre_exchange() override;
  void post_neighbor() override;
  void post_run() override;
  void write_restart(FILE *) override;
  void restart(char *) override {}
  double memory_usage() override;

  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  int pack_restart(int, double *) override;
  void unpack_restart(int, int) override;
  int size_restart(int) override;
  int maxsize_restart() override;

  // Per neighbour-list entry, valid while `live`: entry `first[ii] + jj` is the jj-th
  // neighbour of ilist[ii]; `state` is in the perspective of that list atom i (body 1).
  std::vector<bigint> first;
  std::vector<unsigned char> touch;
  std::vector<rsl_contact_state> state;
  // Per entry, only while the pair style tracks energy (else empty): the elastic energy of the
  // contact's sliding, rolling and twisting springs after its last step, and its normal force's
  // potential (JKR's neck energy), ENERGIES per entry. The pair style counts the springs' as
  // dissipated by the sliders when the contact ends and its history is dropped (and a JKR
  // neck's as lost in the neck's breaking); it moves with the history (per atom, exchange,
  // restart files) for that.
  static constexpr int ENERGIES = 4;
  std::vector<double> elastic;
  // Makes the per-entry arrays current (from the per-atom lists if they are the current copy).
  void ensure_entries()
  {
    if (!live) build_entries();
  }

  PairGranularRollslide *pair = nullptr;

 private:
  struct Partner {
    tagint tag;    // the partner's atom ID
    rsl_contact_state state;    // this atom as body 1, the partner as body 2
  };
  // Packed as doubles: the tag, the 13 doubles of the state, its slip flags as a number (the
  // integer fields are converted, never sent as raw bits); with energies, their 4 after them
  // (restart files written before the normal one have 3: read with the normal one 0).
  static constexpr int PARTNER_DOUBLES = 15;
  static constexpr int ENERGY_DOUBLES = ENERGIES;
  static constexpr int OLD_ENERGY_DOUBLES = 3;
  static void pack_partner(const Partner &, double *);
  static void unpack_partner(const double *, Partner &);
  std::vector<std::vector<Partner>> partners;    // per local atom, valid while !live
  // Per local atom: empty, or the energies of `elastic` for each of its partners (same order),
  // written when the entries had them (energy tracking).
  std::vector<std::vector<std::array<double, ENERGIES>>> partner_elastic;
  // The doubles per partner of atom i's packed records.
  int record_doubles(int i) const
  {
    return partner_elastic[i].empty() ? PARTNER_DOUBLES : PARTNER_DOUBLES + ENERGY_DOUBLES;
  }
  int pack_partners(int i, double *buf) const;
  int unpack_partners(int i, const double *buf, int n, int per);
  bool live = false;    // the per-entry arrays (true) or the per-atom lists (false) hold the history

  void to_atoms();
  void build_entries();
  void update_maxexchange();
};

}    // namespace LAMMPS_NS

#endif
