"""Contact interfaces with many node pairs: finite-element structures, reduction, coupled DLFT, nodal wear."""
