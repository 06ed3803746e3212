# The demo needs only the poses its motion visits.
AVATAR_FLAGS := --poses apose,tpose,armsup
# The fabric the customer buys: 1.50 m wide (make-marker nests the pattern on it).
FABRIC_WIDTH := 1.50
