#version 450 core
// Fault traces: flat colour into the colour attachment only. The ID attachment is masked
// off by the caller (glColorMaski), so traces never change a record id.

uniform vec4 uColour;

layout(location = 0) out vec4 oColour;

void main() { oColour = uColour; }
