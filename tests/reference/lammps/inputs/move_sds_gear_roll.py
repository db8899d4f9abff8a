from tablemove import make
Table = make('motion_sds_gear_roll.txt')
