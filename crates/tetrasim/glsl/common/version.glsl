// Shared header: GLSL version and extensions every compute pass uses.
#extension GL_EXT_scalar_block_layout : require
