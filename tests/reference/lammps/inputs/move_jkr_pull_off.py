from tablemove import make
Table = make('motion_jkr_pull_off.txt')
