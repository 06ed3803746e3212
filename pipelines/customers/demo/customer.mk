# The demo needs only the poses its motion visits.
AVATAR_FLAGS := --poses apose,tpose,armsup
# The fabric the customer buys: 1.50 m wide (make-marker nests the pattern on it).
FABRIC_WIDTH := 1.50
# The verification also judges the movement: two in-between frames of each
# 30-frame transition solved to equilibrium (adapt/README.md, "The movement
# between the key poses"; about a quarter more CPU on this fit).
SIMULATE_FLAGS := --verify-frame-stride 10
