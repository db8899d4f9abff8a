from tablemove import make
Table = make('motion_marshall_rigid_rotation.txt')
