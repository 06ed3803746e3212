# The shared registered body (../shared/avatars), shirt designed on the T-pose.
REGISTER_FLAGS := --reference slim_tpose
# The shirt hugs the body: settling at the key poses with a hundredth of the
# damping lets the cloth reach its equilibrium sooner (992 steps and 53 s
# against 1,048 and 62 s, the same rest growth x1.40 and stretch figures; see
# settle_damping in common/adapt/garment_motion.h).
SIMULATE_FLAGS := --settle-damping 0.01
