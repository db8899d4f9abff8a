from tablemove import make
Table = make('motion_sds_roll_reverse_unload.txt')
