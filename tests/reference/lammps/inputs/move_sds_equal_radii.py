from tablemove import make
Table = make('motion_sds_equal_radii.txt')
