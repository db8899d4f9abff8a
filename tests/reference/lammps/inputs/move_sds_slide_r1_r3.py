from tablemove import make
Table = make('motion_sds_slide_r1_r3.txt')
