#version 450
#extension GL_GOOGLE_include_directive : require
#define TC_F64 0
#include "eval.glsl"
