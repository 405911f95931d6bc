; Case and spacing variants.
; expect motions 3
; expect end 0 1.5 2 0
; expect end 1 3 2 0
; expect end 2 3 0.5 -1
; expect exit 0
g21g90
g1x1.5 y2 f200
G 1 X 3
g01 y.5 z-1.
m2
