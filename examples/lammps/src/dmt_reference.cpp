// For the LAMMPS tests only (built with -DROLLSLIDE_DMT_REFERENCE=ON): registers stock's
// pair granular and fix wall/gran, compiled from LAMMPS' source with DMT's cohesion set
// (examples/lammps/CMakeLists.txt), as `pair_style granular/dmt_reference` and
// `fix wall/gran/dmt_reference`: the reference the tests compare rollslide's DMT rows with.
#include "fix_wall_gran.h"
#include "force.h"
#include "modify.h"
#include "pair_granular.h"

using namespace LAMMPS_NS;

namespace {
Pair *create_pair(LAMMPS *lmp) { return new PairGranularDmtReference(lmp); }
Fix *create_wall(LAMMPS *lmp, int narg, char **arg)
{
  return new FixWallGranDmtReference(lmp, narg, arg);
}
}    // namespace

void rollslide_register_dmt_reference(LAMMPS *lmp)
{
  (*lmp->force->pair_map)["granular/dmt_reference"] = &create_pair;
  (*lmp->modify->fix_map)["wall/gran/dmt_reference"] = &create_wall;
}
