from tablemove import make
Table = make('motion_dmt_random.txt')
