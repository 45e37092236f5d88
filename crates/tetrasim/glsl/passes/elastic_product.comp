#version 460
// Pass `elastic_product`: passes/elastic_product.glsl.
#include "passes/elastic_product.glsl"
