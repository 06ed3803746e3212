# The shared registered body (../shared/avatars), the example shirt in cotton poplin (common/fabric), designed on the T-pose.
REGISTER_FLAGS := --reference slim_tpose
# The shirt hugs the body: settling at the key poses with a hundredth of the
# damping lets the cloth reach its equilibrium sooner (960 steps and 34 s
# against 984 and 39 s, rest growth x1.394 against x1.402, the same stretch
# figures; see SettleOptions::damping in common/adapt/garment_motion.h).
SIMULATE_FLAGS := --settle-damping 0.01
