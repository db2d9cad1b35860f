// A mesh curled before its instance places it (draw_list.hpp, MeshInstance::bend_rad_per_unit): the
// +x axis bends toward +z along a circle of radius 1 / k, a point at x turning k * x radians about -y.
// Included by mesh.vert and shadow.vert, so that a cupped petal's shadow is cupped too.
vec3 bent_position(vec3 p, float k) {
    if (abs(k) < 1e-6) return p;
    float a = k * p.x;
    float r = 1.0 / k;
    return vec3((r - p.z) * sin(a), p.y, r - (r - p.z) * cos(a));
}

vec3 bent_direction(vec3 d, float k, float x) {
    float a = k * x;
    return vec3(d.x * cos(a) - d.z * sin(a), d.y, d.x * sin(a) + d.z * cos(a));
}
