#version 450
// One vertex per patch; it carries nothing: the control stage and the evaluation stage find
// their KSQuad through gl_PrimitiveID in the Info-KSQuad table.
void main() {}
