#version 330 core
// Depth only: the shadow framebuffer has no colour attachment.
void main() {}
