// Camera rays, the --camera / --light parsers, and framing a box from outside.
#include "scenes/camera.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "beamtrace/error.hpp"

namespace beamtrace::scenes {
namespace {

Camera looking_down_minus_z() {
    Camera c;
    c.eye = {1, 2, 10};
    c.at = {1, 2, 0};
    c.fovy_degrees = 60;
    return c;
}

// The message of the beamtrace::Error that `f` throws ("" if it throws nothing).
template <class F>
std::string error_of(F f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(Camera, CentreRayGoesTowardAt) {
    Camera c;
    c.eye = {3, -1, 2};
    c.at = {-4, 5, 7};
    const Float3 toward = normalize(c.at - c.eye);
    const Ray r = c.primary_ray(50, 50, 101, 101);  // the middle pixel of an odd-sized image
    EXPECT_GT(dot(r.dir, toward), 0.999999f);
    EXPECT_EQ(r.org, c.eye);
    EXPECT_EQ(r.tnear, 0.0f);
    EXPECT_EQ(r.tfar, kInfinity);
    // In an even-sized image the four middle pixels surround the view direction symmetrically.
    const Float3 sum = c.primary_ray(49, 49, 98, 98).dir + c.primary_ray(48, 49, 98, 98).dir +
                       c.primary_ray(49, 48, 98, 98).dir + c.primary_ray(48, 48, 98, 98).dir;
    EXPECT_GT(dot(normalize(sum), toward), 0.999999f);
}

TEST(Camera, DirectionsAreNormalised) {
    const Camera c = looking_down_minus_z();
    for (int py : {0, 17, 63})
        for (int px : {0, 40, 127}) EXPECT_NEAR(length(c.primary_ray(px, py, 128, 64).dir), 1.0f, 1e-6f);
}

TEST(Camera, TopRowPointsUpLeftColumnPointsLeft) {
    const Camera c = looking_down_minus_z();
    for (int px : {0, 31, 63}) {
        EXPECT_GT(c.primary_ray(px, 0, 64, 48).dir.y, 0.0f) << "top row, column " << px;
        EXPECT_LT(c.primary_ray(px, 47, 64, 48).dir.y, 0.0f) << "bottom row, column " << px;
    }
    for (int py : {0, 23, 47}) {
        EXPECT_LT(c.primary_ray(0, py, 64, 48).dir.x, 0.0f) << "left column, row " << py;
        EXPECT_GT(c.primary_ray(63, py, 64, 48).dir.x, 0.0f) << "right column, row " << py;
    }
    // Moving down the image the rays turn steadily downward.
    for (int py = 1; py < 48; ++py)
        EXPECT_LT(c.primary_ray(10, py, 64, 48).dir.y, c.primary_ray(10, py - 1, 64, 48).dir.y);
}

TEST(Camera, FieldOfViewIsVerticalAndAspectWidensIt) {
    Camera c = looking_down_minus_z();
    c.fovy_degrees = 90;
    const int h = 1000;
    // Centre of the top row: half a pixel inside the top edge of a 90 degree field of view.
    const Ray top = c.primary_ray(h - 1, 0, 2 * h - 1, h);
    EXPECT_NEAR(top.dir.y / -top.dir.z, 1.0f - 1.0f / h, 1e-4f);
    EXPECT_NEAR(top.dir.x, 0.0f, 1e-6f);
    // A 2:1 image sees twice as far sideways.
    const Ray right = c.primary_ray(2 * h - 1, h / 2, 2 * h, h);
    EXPECT_NEAR(right.dir.x / -right.dir.z, 2.0f * (1.0f - 0.5f / h), 1e-3f);
}

TEST(Camera, WorksWhenLookingAlongUp) {
    for (float s : {1.0f, -1.0f}) {
        Camera c;
        c.eye = {0, 5 * s, 0};
        c.at = {0, 0, 0};  // straight down (or up): parallel to the default up vector
        const Camera::Basis b = c.basis();
        EXPECT_NEAR(dot(b.forward, b.right), 0.0f, 1e-6f);
        EXPECT_NEAR(dot(b.forward, b.up), 0.0f, 1e-6f);
        EXPECT_NEAR(length(b.right), 1.0f, 1e-6f);
        const Ray centre = c.primary_ray(8, 8, 17, 17);
        EXPECT_NEAR(centre.dir.y, -s, 1e-6f);
        const Ray corner = c.primary_ray(0, 0, 17, 17);
        EXPECT_TRUE(std::isfinite(corner.dir.x) && std::isfinite(corner.dir.y) && std::isfinite(corner.dir.z));
        EXPECT_LT(dot(corner.dir, centre.dir), 0.95f);  // corners really spread out
    }
}

TEST(Camera, PrimaryRayRejectsBadCameraAndImage) {
    Camera c = looking_down_minus_z();
    EXPECT_NE(error_of([&] { c.primary_ray(0, 0, 0, 10); }).find("image size"), std::string::npos);
    c.at = c.eye;
    EXPECT_NE(error_of([&] { c.primary_ray(0, 0, 10, 10); }).find("same point"), std::string::npos);
    c = looking_down_minus_z();
    c.fovy_degrees = 180;
    EXPECT_NE(error_of([&] { c.primary_ray(0, 0, 10, 10); }).find("FOVY"), std::string::npos);
}

TEST(ParseCamera, ReadsSevenNumbers) {
    const Camera c = parse_camera(" 1, 2.5 ,-3, +4,5e1,6 ,45 ");
    EXPECT_EQ(c.eye, (Float3{1, 2.5f, -3}));
    EXPECT_EQ(c.at, (Float3{4, 50, 6}));
    EXPECT_EQ(c.fovy_degrees, 45.0f);
    EXPECT_EQ(c.up, (Float3{0, 1, 0}));
}

TEST(ParseCamera, ErrorsNameTheBadField) {
    auto message = [](const std::string& text) { return error_of([&] { parse_camera(text); }); };
    EXPECT_NE(message("1,2,3").find("expected 7 comma-separated numbers EX,EY,EZ,AX,AY,AZ,FOVY, got 3"),
              std::string::npos);
    EXPECT_NE(message("1,2,3,4,5,6,7,8").find("got 8"), std::string::npos);
    EXPECT_NE(message("").find("got 1"), std::string::npos);
    const std::string bad_ez = message("1,2,x,4,5,6,60");
    EXPECT_NE(bad_ez.find("EZ"), std::string::npos) << bad_ez;
    EXPECT_NE(bad_ez.find("not a number: \"x\""), std::string::npos) << bad_ez;
    EXPECT_NE(message("1,2,3,4,5,,60").find("field AZ (6th) is not a number"), std::string::npos);
    EXPECT_NE(message("1,2,3,4,5,6,60deg").find("FOVY"), std::string::npos);
    EXPECT_NE(message("nan,2,3,4,5,6,60").find("EX (1st) is not a finite number"), std::string::npos);
    EXPECT_NE(message("1,2,3,4,5,6,1e99").find("FOVY (7th) is not a finite number"), std::string::npos);
    EXPECT_NE(message("1,2,3,1,2,3,60").find("same point"), std::string::npos);
    for (const char* fov : {"0", "180", "-10", "200"}) {
        const std::string m = message(std::string("0,0,5,0,0,0,") + fov);
        EXPECT_NE(m.find("FOVY must be in (0,180)"), std::string::npos) << fov << ": " << m;
    }
    EXPECT_NE(error_of([] { parse_camera("1,2", "--camera"); }).find("--camera: expected 7"), std::string::npos);
}

TEST(ParsePoint, ReadsThreeNumbersAndNamesBadFields) {
    EXPECT_EQ(parse_point("1,-2,3.5"), (Float3{1, -2, 3.5f}));
    const std::string m = error_of([] { parse_point("1,y,3", "--light"); });
    EXPECT_NE(m.find("--light: field Y (2nd) is not a number: \"y\""), std::string::npos) << m;
    EXPECT_NE(error_of([] { parse_point("1,2"); }).find("expected 3 comma-separated numbers X,Y,Z, got 2"),
              std::string::npos);
    EXPECT_NE(error_of([] { parse_point("1,2,inf"); }).find("Z (3rd) is not a finite number"), std::string::npos);
}

// Where a point lands in the image plane of `c`: (x, y) in units of tan(fovy / 2); depth > 0 if in front.
struct Projection {
    float x, y, depth;
};
Projection project(const Camera& c, Float3 p) {
    const Camera::Basis b = c.basis();
    const Float3 v = p - c.eye;
    const float depth = dot(v, b.forward);
    const float t = std::tan(c.fovy_degrees * std::numbers::pi_v<float> / 360.0f);
    return {dot(v, b.right) / depth / t, dot(v, b.up) / depth / t, depth};
}

TEST(FrameFromOutside, SeesTheWholeBoxFromOutsideItsBoundingSphere) {
    for (const Box& box : {Box{{0, 0, 0}, {1, 1, 1}}, Box{{-5, 2, 100}, {40, 3, 101}}, Box{{-1, -1, 0}, {1, 1, 0}}}) {
        const Camera c = frame_from_outside(box);
        EXPECT_EQ(c.at, box.center());
        EXPECT_GT(length(c.eye - box.center()), 0.5f * box.diagonal());
        for (int k = 0; k < 8; ++k) {
            const Float3 corner{(k & 1) ? box.upper.x : box.lower.x, (k & 2) ? box.upper.y : box.lower.y,
                                (k & 4) ? box.upper.z : box.lower.z};
            const Projection p = project(c, corner);
            EXPECT_GT(p.depth, 0.0f);
            EXPECT_LE(std::fabs(p.x), 1.0f) << "corner " << k;  // inside a square image
            EXPECT_LE(std::fabs(p.y), 1.0f) << "corner " << k;
        }
        // A 3/4 view: from above, and not straight along an axis.
        EXPECT_GT(c.eye.y, c.at.y);
        EXPECT_NE(c.eye.x, c.at.x);
        EXPECT_NE(c.eye.z, c.at.z);
    }
}

TEST(FrameFromOutside, PointBoxWorksEmptyBoxThrows) {
    Box point;
    point.extend(Float3{2, 3, 4});
    const Camera c = frame_from_outside(point);
    EXPECT_FALSE(c.eye == c.at);
    EXPECT_NO_THROW(c.primary_ray(0, 0, 4, 4));
    EXPECT_NE(error_of([] { frame_from_outside(Box{}); }).find("empty box"), std::string::npos);
}

}  // namespace
}  // namespace beamtrace::scenes
