from tablemove import make
Table = make('motion_dmt_pull_off.txt')
