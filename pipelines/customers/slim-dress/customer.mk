# The shared registered body (../shared/avatars), dress designed on the A-pose.
REGISTER_FLAGS := --reference slim_apose
