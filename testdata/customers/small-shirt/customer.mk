# A small, fast fit for the pipeline and golden-mesh tests: the default body
# in two poses, a ~1,100-vertex shirt, a short motion with a settling cap.
AVATAR_FLAGS   := --poses apose,tpose
SIMULATE_FLAGS := --settle-max-steps 120
