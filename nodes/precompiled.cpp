// Compiles nodes/precompiled.hpp once, with the flags of the node libraries.
