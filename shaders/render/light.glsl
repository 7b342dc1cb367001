// The rectangular area light (renderer/scene/scene.h AreaLight) and the direct-light estimate of one sample.
uniform vec3 lightCorner;
uniform vec3 lightEdgeU;
uniform vec3 lightEdgeV;
uniform vec3 lightRadiance;

// Radiance reflected towards the viewer by a Lambertian surface (albedo, unit normal n, both facing the
// viewer) from one light sample reached along unit `direction` at `distance`, visibility already known:
// L = albedo/π · Le · cosθ_surface · cosθ_light · A / d²  (area-sampling estimator, pdf = 1/A).
vec3 directLightSample(vec3 albedo, vec3 n, vec3 direction, float distance) {
    vec3 lightNormalScaled = cross(lightEdgeU, lightEdgeV); // length = area
    float cosSurface = max(dot(n, direction), 0.0f);
    float cosLightTimesArea = max(-dot(lightNormalScaled, direction), 0.0f);
    return albedo * (1.0f / 3.14159265358979f) * lightRadiance * cosSurface * cosLightTimesArea /
           (distance * distance);
}
