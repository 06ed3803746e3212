# The demo body wearing a dress (the demo shirt's top, its hem extended into a
# skirt), through the pose in which the hands rest beside the thighs, as a
# customer stands in a scanner (make-avatar's handsonthighs: the wrist 5.7 mm
# from the hip), where the skirt has to pass between hand and thigh.
AVATAR_FLAGS := --poses apose,handsonthighs
