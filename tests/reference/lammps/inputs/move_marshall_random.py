from tablemove import make
Table = make('motion_marshall_random.txt')
