#version 460
// Pass `elastic_correction_product` (after the last conjugate-gradient iteration): the product of
// passes/elastic_product.glsl on the rigid-part correction's moves.
#define CORRECTION
#include "passes/elastic_product.glsl"
