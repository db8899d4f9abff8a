// fix ID group wall/gran/rollslide granular <pair granular's keywords> <wallstyle> <args>
//     [wiggle dim A period | shear dim v] [preset objective|lammps]
//
// LAMMPS' `fix wall/gran granular` (20220106) for flat walls (xplane, yplane, zplane) and a
// z cylinder, with pair_style granular/rollslide's subset of the granular keywords. The normal
// force is computed as stock `fix wall/gran granular` computes it (its effective radius, with
// the cylinder's curvature, and its coefficients); the sliding, rolling and twisting loads come
// from rollslide (rsl_contact_step_wall): `lammps` = RSL_PRESET_LAMMPS_2021 (stock's own
// definitions), `objective` (the default) = the library's objective definitions. One contact
// history (rsl_contact_state) per atom, kept through migration between ranks and restart
// files. See docs/lammps.md, "The wall fix".
#ifndef ROLLSLIDE_FIX_WALL_GRAN_ROLLSLIDE_H
#define ROLLSLIDE_FIX_WALL_GRAN_ROLLSLIDE_H

#include "fix.h"
#include "granular_model.h"
#include "rollslide.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class ComputeRollslideEnergy;

class FixWallGranRollslide : public Fix {
 public:
  static constexpr const char *STYLE = "wall/gran/rollslide";

  FixWallGranRollslide(class LAMMPS *, int, char **);
  ~FixWallGranRollslide() override;
  int setmask() override;
  void init() override;
  void setup(int) override;
  void post_force(int) override;
  void write_restart(FILE *) override;
  void restart(char *) override;
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

 private:
  enum WallStyle { XPLANE = 0, YPLANE = 1, ZPLANE = 2, ZCYLINDER = 3 };
  // Which wall an atom's history belongs to: none (no contact), the lo plane (or the inside
  // of the cylinder), the hi plane (or the outside of the cylinder).
  enum Side { NO_WALL = 0, LO = 1, HI = 2 };

  int preset = RSL_PRESET_OBJECTIVE;
  granular::Coeffs coeffs;
  rsl_model *model = nullptr;
  bool model_tracks_energy = false;
  ComputeRollslideEnergy *energy = nullptr;

  int wallstyle = ZPLANE;
  bool has_lo = false, has_hi = false;
  double lo = 0.0, hi = 0.0, cylradius = 0.0;
  bool wiggle = false, wshear = false;
  int axis = 0;
  double amplitude = 0.0, period = 0.0, omega = 0.0, vshear = 0.0;
  bigint time_origin = 0;

  // Per atom: the history of its wall contact (the atom is body 1), which wall it is with, and
  // the elastic energies of its sliding, rolling and twisting springs after the last step (with
  // the energy compute: dissipated by the sliders when the contact ends) and its normal force's
  // potential (a JKR neck's, lost when it breaks). Packed as doubles: the 13 doubles of the
  // state, its slip flags and the side as numbers (integers are converted, never sent as raw
  // bits), the 4 energies.
  static constexpr int ATOM_DOUBLES = 19;
  static constexpr int OLD_ATOM_DOUBLES = 18;    // restart files without the normal energy
  std::vector<rsl_contact_state> history;
  std::vector<int> side;
  // 4 per atom: the sliding, rolling, twisting springs' elastic energy after the contact's last
  // step, and its normal force's potential (a JKR neck's energy, lost if it breaks).
  std::vector<double> spring_energy;

  // The contacts gathered for one batch call (see post_force), and the call's buffers.
  static constexpr size_t CHUNK = 256;
  struct Chunk {
    std::vector<int> atoms;
    std::vector<rsl_sphere> spheres;
    std::vector<rsl_wall> walls;
    std::vector<double> normal_force, sliding_stiffness, sliding_damping;
    std::vector<size_t> state_index;
    std::vector<double> normal_dissipated, normal_elastic;
    bool per_contact_stiffness = false, per_contact_damping = false;
    size_t size() const { return atoms.size(); }
    void clear();
    bool same_coefficients(const granular::NormalForce &nf) const;
    void add(int i, const rsl_sphere &s, const rsl_wall &w, const granular::NormalForce &nf,
             double dissipated);
  };
  Chunk chunk;
  std::vector<uint32_t> sphere_of_contact;    // 0, 1, 2, ...: each contact its own sphere
  std::vector<rsl_vec3> chunk_force, chunk_torque;
  std::vector<rsl_contact_energy> chunk_energy;
  void flush_chunk(double dt);

  [[noreturn]] void fail(const std::string &message);
  [[noreturn]] void library_error(const char *call, int32_t status, tagint atom, int wall_side);
  std::string wall_name(int wall_side) const;
  void make_model(bool track_energy);
  void end_contact(int i);
  void pack_atom(int i, double *buf) const;
  void unpack_atom(const double *buf, int i);
};

}    // namespace LAMMPS_NS

#endif
