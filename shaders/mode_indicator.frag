#version 450 core
// The mode indicator: a coloured plate with the mode's name in a 5x7 bitmap font.
uniform vec3 u_plate;
uniform vec2 u_origin_px;  // bottom-left of the plate, window pixels
uniform float u_cell_px;
uniform int u_font[70];    // 10 glyphs x 7 rows of 5 bits
uniform int u_text[12];
uniform int u_length;
out vec4 o_colour;
void main() {
    ivec2 cell = ivec2(floor((gl_FragCoord.xy - u_origin_px) / u_cell_px));
    int col = cell.x - 1, row = 7 - cell.y;   // one cell of margin left and bottom
    bool ink = false;
    if (col >= 0 && row >= 0 && row < 7 && col / 6 < u_length && col % 6 < 5) {
        int bits = u_font[u_text[col / 6] * 7 + row];
        ink = ((bits >> (4 - col % 6)) & 1) != 0;
    }
    o_colour = vec4(ink ? vec3(0.0) : u_plate, 1.0);
}
