from tablemove import make
Table = make('motion_jkr_random.txt')
