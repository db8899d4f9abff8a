from tablemove import make
Table = make('motion_sds_rigid_rotation.txt')
