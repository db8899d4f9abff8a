from tablemove import make
Table = make('motion_sds_twist.txt')
