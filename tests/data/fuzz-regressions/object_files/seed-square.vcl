title    vertex color file for a square
data 4
.9 .8 .2 .0 .0 .0
.8 .9 .2 .0 .0 .0
.2 .8 .9 .0 .0 .0
.9 .2 .8 .0 .0 .0
