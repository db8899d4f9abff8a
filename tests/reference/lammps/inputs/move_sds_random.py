from tablemove import make
Table = make('motion_sds_random.txt')
