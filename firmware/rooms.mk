# firmware/rooms.mk - the rooms of firmware/, bottom up: a room includes
# and calls only itself and the rooms before it (firmware/README.md says
# what each holds). Read by the Makefile, firmware/f28335/target.mk and
# the layer gate (tools/check/layers.sh).
FIRMWARE_ROOMS := params protect commission app link f28335
