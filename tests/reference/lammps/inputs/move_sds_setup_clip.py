from tablemove import make
Table = make('motion_sds_setup_clip.txt')
