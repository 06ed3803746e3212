# The demo needs only the poses its motion visits.
AVATAR_FLAGS := --poses apose,tpose,armsup
