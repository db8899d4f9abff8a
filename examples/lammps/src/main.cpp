// lmp_rollslide: stock LAMMPS (Debian's liblammps 20220106) with rollslide's styles registered.
// Same command line as `lmp` (-in, -var, -log, -screen, ...), under mpirun or alone.
#include "compute_rollslide_energy.h"
#include "fix_rollslide_history.h"
#include "fix_wall_gran_rollslide.h"
#include "pair_granular_rollslide.h"

#include "force.h"
#include "input.h"
#include "lammps.h"
#include "modify.h"

#include <mpi.h>

#ifdef ROLLSLIDE_DMT_REFERENCE
// For the tests: stock's classes with DMT's cohesion set (src/dmt_reference.cpp).
void rollslide_register_dmt_reference(LAMMPS_NS::LAMMPS *lmp);
#endif

using namespace LAMMPS_NS;

namespace {
Pair *create_pair(LAMMPS *lmp) { return new PairGranularRollslide(lmp); }
Fix *create_fix(LAMMPS *lmp, int narg, char **arg) { return new FixRollslideHistory(lmp, narg, arg); }
Fix *create_wall(LAMMPS *lmp, int narg, char **arg) { return new FixWallGranRollslide(lmp, narg, arg); }
Compute *create_energy(LAMMPS *lmp, int narg, char **arg)
{
  return new ComputeRollslideEnergy(lmp, narg, arg);
}
}    // namespace

int main(int argc, char **argv)
{
  MPI_Init(&argc, &argv);
  LAMMPS *lmp = new LAMMPS(argc, argv, MPI_COMM_WORLD);
  // Registered before the input is read, as LAMMPS registers its own styles.
  (*lmp->force->pair_map)["granular/rollslide"] = &create_pair;
  (*lmp->modify->fix_map)[FixRollslideHistory::STYLE] = &create_fix;
  (*lmp->modify->fix_map)[FixWallGranRollslide::STYLE] = &create_wall;
  (*lmp->modify->compute_map)[ComputeRollslideEnergy::STYLE] = &create_energy;
#ifdef ROLLSLIDE_DMT_REFERENCE
  rollslide_register_dmt_reference(lmp);
#endif
  lmp->input->file();
  delete lmp;
  MPI_Barrier(MPI_COMM_WORLD);
  MPI_Finalize();
  return 0;
}
