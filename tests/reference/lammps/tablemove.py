"""Impose tabulated motion in LAMMPS through `fix python/move`.

initial_integrate() of step k (update->ntimestep already equals k) overwrites
x, v and omega of atoms 1 and 2 with row k of the table; final_integrate() does
nothing.  No integrator is defined, so forces never feed back on the motion.
Table rows: step x1 y1 z1 x2 y2 z2 v1 v2 w1 w2 (19 numbers, repr() precision).
"""
from lammps import lammps


class LAMMPSFix(object):
    def __init__(self, ptr, group_name="all"):
        self.lmp = lammps(ptr=ptr)
        self.group_name = group_name


class LAMMPSFixMove(LAMMPSFix):
    def __init__(self, ptr, group_name="all"):
        super(LAMMPSFixMove, self).__init__(ptr, group_name)

    def init(self):
        pass

    def initial_integrate(self, vflag):
        pass

    def final_integrate(self):
        pass

    def initial_integrate_respa(self, vflag, ilevel, iloop):
        pass

    def final_integrate_respa(self, ilevel, iloop):
        pass

    def reset_dt(self):
        pass


def make(path):
    table = {}
    with open(path) as fh:
        for line in fh:
            if line.startswith("#"):
                continue
            a = line.split()
            table[int(a[0])] = [float(s) for s in a[1:]]

    class Table(LAMMPSFixMove):
        def __init__(self, ptr, group_name="all"):
            super(Table, self).__init__(ptr, group_name)

        def initial_integrate(self, vflag):
            k = self.lmp.extract_global("ntimestep")
            row = table[k]
            x = self.lmp.extract_atom("x")
            v = self.lmp.extract_atom("v")
            w = self.lmp.extract_atom("omega")
            tag = self.lmp.extract_atom("id")
            for i in range(2):
                b = tag[i] - 1
                for d in range(3):
                    x[i][d] = row[3 * b + d]
                    v[i][d] = row[6 + 3 * b + d]
                    w[i][d] = row[12 + 3 * b + d]

    return Table
