"""Hardware-in-the-loop: the drive-electronics emulator that talks to a stage-model node
(stickslip_node, or the firmware) over a serial link (docs/protocol.md)."""
