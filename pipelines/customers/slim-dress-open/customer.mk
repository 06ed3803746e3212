# The slim-dress on the same body, with its A-pose opened: in the capture the
# left hand rests 6.5 mm from the thigh, where the skirt (8 mm offset) has to
# pass, and the hand holds the cloth. Here the A-pose is the body 1/20 of the
# way to the T-pose (the arms about 3 degrees further from the body; the hand
# 47 mm from the thigh), the other poses as captured.
REGISTER_FLAGS := --reference slim_apose
OPEN_POSE   := slim_apose
OPEN_TOWARD := slim_tpose
OPEN_STEPS  := 20
