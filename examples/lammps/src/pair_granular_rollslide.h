// pair_style granular/rollslide [objective|lammps]
//
// LAMMPS' pair_style granular (20220106) for the subset: normal hooke | hertz | hertz/material |
// dmt | jkr (JKR's necks beyond touching until pull-off; the cohesive models' contacts step one
// at a time, with LAMMPS' per-contact limit force),
// damping velocity | mass_velocity | viscoelastic | tsuji, tangential linear_nohistory |
// linear_history | mindlin | mindlin_rescale | mindlin/force | mindlin_rescale/force, rolling
// sds, twisting sds | marshall, limit_damping, cutoff. The normal force is computed
// here as LAMMPS computes it; the sliding, rolling and twisting loads come from rollslide:
// `lammps` = RSL_PRESET_LAMMPS_2021 (LAMMPS' own definitions, step by step), `objective` (the
// default) = the library's objective definitions with the same coefficients.
#ifndef ROLLSLIDE_PAIR_GRANULAR_ROLLSLIDE_H
#define ROLLSLIDE_PAIR_GRANULAR_ROLLSLIDE_H

#include "granular_model.h"
#include "pair.h"
#include "rollslide.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class ComputeRollslideEnergy;
class FixRollslideHistory;

class PairGranularRollslide : public Pair {
 public:
  PairGranularRollslide(class LAMMPS *);
  ~PairGranularRollslide() override;
  void compute(int, int) override;
  void settings(int, char **) override;
  void coeff(int, char **) override;
  void init_style() override;
  double init_one(int, int) override;
  double single(int, int, int, int, double, double, double, double &) override;
  double memory_usage() override;

  // The model of a type pair (the swap of a state and the per-contact setup pass need it).
  const rsl_model *model(int itype, int jtype) const { return models[itype * (ntypes + 1) + jtype]; }
  // A LAMMPS error naming the pair's atom IDs and the library's message; never returns.
  [[noreturn]] void library_error(const char *call, int32_t status, tagint id1, tagint id2);
  [[noreturn]] void fail(const std::string &message);
  // Whether the contact passes collect energy (a compute rollslide/energy or pair/local exists).
  bool tracks_energy() const { return track; }

  using Coeffs = granular::Coeffs;

 private:
  int preset = RSL_PRESET_OBJECTIVE;
  int ntypes = 0;
  std::vector<Coeffs> coeffs;        // (ntypes+1)^2
  std::vector<rsl_model *> models;   // (ntypes+1)^2, built by init_style

  // The batch calls step a chunk of contacts with one model, and a model with a table of
  // coefficient sets (rsl_model_set_materials) steps contacts of several type pairs, each with
  // its own pair's set (its index in params.material), as long as the pairs' library laws
  // agree. So the type pairs are grouped by law set (rolling sds or none, twisting sds, marshall
  // or none, and what the sliding spring stores, RSL_SLIDING_HISTORY_*: the sliding law is
  // linear for all, and the normal force is computed here), and a
  // chunk holds the contacts of one group: with one law set for all type pairs, a chunk no
  // longer ends where the type pair changes along the neighbour list.
  struct Group {
    // A group of one type pair steps with that pair's model (in `models`), without a table;
    // a larger group with a model of its own (`owned`) holding a table over its pairs.
    rsl_model *model = nullptr;
    bool owned = false;
    // Some pair of the group has a per-contact k_t (the mindlin family) or gamma_t (every
    // damping model but velocity): then every contact of the group passes one (its pair's
    // constant for the others, the value of its set, so the step is the same).
    bool kt = false, gammat = false;
  };
  std::vector<Group> groups;
  // Per type pair (itype * (ntypes+1) + jtype): its group, and its index in the group's table.
  struct Slot {
    int group = -1;
    uint32_t material = 0;
  };
  std::vector<Slot> slots;
  bool any_jkr = false;    // a type pair has the jkr normal model (its necks reach beyond touching)
  std::vector<double> maxrad;        // per type
  FixRollslideHistory *history = nullptr;
  int freeze_group_bit = 0;
  double dt = 0.0;

  // Energy (see the .cpp's "Energy" comment). `energy`: the compute rollslide/energy that
  // receives every stepped contact's energy, if one is defined; `per_contact`: a compute
  // pair/local is defined, and each contact's dissipation rates of its last pass are kept for
  // single(); `track`: either, the models track energy and the passes collect it.
  ComputeRollslideEnergy *energy = nullptr;
  bool per_contact = false;
  bool track = false;
  static constexpr int NRATES = 7;      // single()'s values, per neighbour-list entry
  std::vector<double> contact_rates;    // NRATES per entry of the history (per_contact)
  std::vector<unsigned> rates_pass;     // per entry: the pass that wrote its rates (per_contact)
  unsigned pass = 0;                    // contact passes so far (per_contact)
  std::vector<int> list_index;          // per local atom: its ii in the list, or -1 (per_contact)

  // Contacts are stepped in chunks of up to CHUNK, one library call per chunk, one group's
  // model (hence one law set) per chunk. Two kinds of chunk are filled side by side:
  // - `direct`: contacts between two local atoms, stepped by rsl_batch_step_params
  //   (particle-major) from the step's sphere array (`spheres`, one record per local and ghost
  //   atom, filled once per step), the library adding the loads straight into atom->f and
  //   atom->torque;
  // - `paired`: contacts with a ghost atom j (whose loads only atom i takes, as the list is
  //   newton off), and every contact of a step that tallies energy or virial (which needs
  //   each pair's force), stepped by rsl_batch_step_contacts_params from two sphere records per
  //   contact, the loads applied here.
  static constexpr int CHUNK = 512;
  struct Pending {
    int i, j;
    bigint e;
    double del[3];
  };
  struct Chunk {
    // The chunk's contacts, pending[0..n): a fixed array written field by field (a push_back of
    // a brace-built Pending made GCC assemble it on the stack and copy it with wider loads than
    // its stores, a store-forwarding stall that took a fifth of compute()'s samples).
    std::vector<Pending> pending;
    int n = 0;
    std::vector<uint32_t> pairs;            // direct: atom indices i, j per contact
    std::vector<rsl_sphere> body1, body2;   // paired: the two sphere records per contact
    std::vector<double> normal_force;
    // Per-contact k_t (the mindlin family) and gamma_t (every damping model but velocity).
    std::vector<double> sliding_stiffness, sliding_damping;
    std::vector<uint32_t> material;         // each contact's index in its group's table
    std::vector<size_t> index;              // direct: each contact's entry in the history
    std::vector<rsl_contact_state> state;   // paired: the histories, copied in and out
    std::vector<rsl_batch_loads> loads;     // paired only
    // With energy tracking: the library's energy terms, the normal dashpot's dissipation and the
    // normal spring's energy, per contact.
    std::vector<rsl_contact_energy> energy;
    std::vector<double> normal_dissipated, normal_elastic;
    void resize(bool direct, bool energy);
  };
  Chunk direct, paired;
  std::vector<rsl_sphere> spheres;          // per local and ghost atom, this step
  int chunk_group = -1;                     // the group of the pending contacts, -1: none

  Coeffs &at(int i, int j) { return coeffs[i * (ntypes + 1) + j]; }
  void allocate();
  rsl_model *new_model(const Coeffs &c, int i, int j);
  void build_groups();
  void free_models();
  rsl_batch_contact_params chunk_params(Chunk &ch) const;
  void load_states(Chunk &ch);
  [[noreturn]] void chunk_error(const char *call, int32_t status, const rsl_batch_report &report,
                                const Chunk &ch);
  template <bool ENERGY> void compute_contacts(bool setup);
  void tally(int i, int j, bigint e, const rsl_contact_energy &en, double normal_dissipated,
             double normal_elastic);
  void tally_chunk(const Chunk &ch);
  void release(int i, int j, bigint e);
  bigint find_entry(int i, int j) const;
  void flush_direct();
  void flush_paired();
  void flush()
  {
    flush_direct();
    flush_paired();
  }
  void apply(int i, int j, const double del[3], const rsl_vec3 &force1, const rsl_vec3 &torque1,
             const rsl_vec3 &torque2);
};

}    // namespace LAMMPS_NS

#endif
