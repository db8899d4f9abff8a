from tablemove import make
Table = make('motion_marshall_gear_roll.txt')
