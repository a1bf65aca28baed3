// "room" / "room:SEED": a furnished classroom, the occlusion-heavy interior of the papers' walkthrough
// scenes (VLF-RT's "Classroom", MLRTA's conference room), at about a million triangles.
//
// A closed shell (floor, ceiling and four walls as one inward-facing box: no gaps), a pillar, a
// blackboard, ceiling lights, a bookshelf full of books, a teacher's desk and four rows of four desks
// with chairs. On every desk stand finely tessellated objects (balls, rings, teapots, vases, cups,
// knots, bottles, ring towers; about 15,000 triangles each), 68 in all. The seed jitters desks and
// chairs, fills the bookshelf and picks, places, sizes and turns the desk objects; the triangle count
// stays within about 1.01-1.03 million for every seed. Every part is a closed mesh.
//
// Units are metres; +y is up. The room spans x 0..12, z 0..9, the blackboard is on the z = 0 wall and
// the pupils face it (-z). The default camera stands near the back-left corner at eye height.
#include <numbers>
#include <string>

#include "scenes/desk_objects.hpp"
#include "scenes/deterministic_random.hpp"
#include "scenes/generators.hpp"
#include "scenes/mesh_builder.hpp"

namespace beamtrace::scenes {

namespace {

constexpr float kWidth = 12.0f, kHeight = 3.2f, kDepth = 9.0f;
constexpr float kDeskTop = 0.76f;

Box box(float x0, float x1, float y0, float y1, float z0, float z1) { return Box{{x0, y0, z0}, {x1, y1, z1}}; }

// A desk of the given size centred at (x, z): a top and four legs.
void add_desk(MeshBuilder& m, float x, float z, float half_width, float half_depth) {
    constexpr float kThick = 0.04f, kLeg = 0.05f, kInset = 0.04f;
    m.add_box(box(x - half_width, x + half_width, kDeskTop - kThick, kDeskTop, z - half_depth, z + half_depth));
    for (float sx : {-1.0f, 1.0f})
        for (float sz : {-1.0f, 1.0f}) {
            const float lx = x + sx * (half_width - kInset - kLeg / 2), lz = z + sz * (half_depth - kInset - kLeg / 2);
            m.add_box(box(lx - kLeg / 2, lx + kLeg / 2, 0.0f, kDeskTop - kThick, lz - kLeg / 2, lz + kLeg / 2));
        }
}

// A chair centred at (x, z) facing -z: seat, four legs and a backrest on the +z side.
void add_chair(MeshBuilder& m, float x, float z) {
    constexpr float kHalf = 0.22f, kSeat = 0.45f, kThick = 0.04f, kLeg = 0.04f;
    m.add_box(box(x - kHalf, x + kHalf, kSeat - kThick, kSeat, z - kHalf, z + kHalf));
    for (float sx : {-1.0f, 1.0f})
        for (float sz : {-1.0f, 1.0f}) {
            const float lx = x + sx * (kHalf - kLeg / 2), lz = z + sz * (kHalf - kLeg / 2);
            m.add_box(box(lx - kLeg / 2, lx + kLeg / 2, 0.0f, kSeat - kThick, lz - kLeg / 2, lz + kLeg / 2));
        }
    m.add_box(box(x - kHalf, x + kHalf, kSeat, 0.92f, z + kHalf - kThick, z + kHalf));
}

// `count` objects in a row along x on a desk top centred at (x, z): each in its own slot, jittered,
// sized and turned by the random stream.
void add_desk_objects(MeshBuilder& m, DeterministicRandom& random, float x, float z, float half_width, float half_depth,
                      int count, int coarseness) {
    const float slot = 2.0f * half_width / static_cast<float>(count);
    for (int i = 0; i < count; ++i) {
        const auto kind = static_cast<DeskObject>(random.below(kDeskObjectKinds));
        const float footprint = random.uniform(0.09f, 0.13f);
        const float free_x = slot / 2 - footprint - 0.01f, free_z = half_depth - footprint - 0.03f;
        const float cx = x - half_width + slot * (static_cast<float>(i) + 0.5f) + random.uniform(-free_x, free_x);
        const float cz = z + random.uniform(-free_z, free_z);
        const float yaw = random.uniform(0.0f, 2.0f * std::numbers::pi_v<float>);
        m.begin_object();
        add_desk_object(m, kind, {cx, kDeskTop, cz}, footprint, yaw, coarseness);
    }
}

// A bookshelf against the x = kWidth wall between z0 and z1: two sides, five boards, books on four.
void add_bookshelf(MeshBuilder& m, DeterministicRandom& random, float z0, float z1) {
    constexpr float kFront = kWidth - 0.4f, kBoard = 0.03f, kTop = 2.0f;
    m.begin_object();  // the two sides
    m.add_box(box(kFront, kWidth, 0.0f, kTop, z0, z0 + kBoard));
    m.add_box(box(kFront, kWidth, 0.0f, kTop, z1 - kBoard, z1));
    for (int shelf = 0; shelf < 5; ++shelf) {
        m.begin_object();  // each board with the books standing on it
        const float y = shelf == 4 ? kTop - kBoard : 0.5f * static_cast<float>(shelf);
        m.add_box(box(kFront, kWidth, y, y + kBoard, z0 + kBoard, z1 - kBoard));
        if (shelf == 4) continue;
        for (float z = z0 + kBoard + 0.01f;;) {
            const float thick = random.uniform(0.025f, 0.07f), tall = random.uniform(0.25f, 0.42f);
            const float deep = random.uniform(0.2f, 0.32f);
            if (z + thick > z1 - kBoard - 0.01f) break;
            m.add_box(box(kFront + 0.04f, kFront + 0.04f + deep, y + kBoard, y + kBoard + tall, z, z + thick));
            z += thick + random.uniform(0.002f, 0.01f);
        }
    }
}

SceneSource make_room(std::uint32_t seed, int coarseness) {
    DeterministicRandom random(seed);
    MeshBuilder m;
    if (coarseness == 1) m.reserve(560'000, 1'040'000);

    // Objects (SceneSource::object_of_triangle): the shell, the pillar, the blackboard, each light,
    // the bookshelf's sides and each board with its books, each desk, desk object and chair.
    m.begin_object();
    m.add_box(box(0, kWidth, 0, kHeight, 0, kDepth), Facing::inward);  // floor, ceiling and walls
    m.begin_object();
    m.add_box(box(5.7f, 6.3f, 0, kHeight, 4.3f, 4.9f));  // the pillar, in the middle aisle
    m.begin_object();
    m.add_box(box(4.0f, 8.0f, 0.9f, 2.1f, 0.0f, 0.04f));  // blackboard
    for (float x : {3.0f, 6.0f, 9.0f})                    // ceiling lights
        for (float z : {3.0f, 6.5f}) {
            m.begin_object();
            m.add_box(box(x - 0.6f, x + 0.6f, kHeight - 0.06f, kHeight, z - 0.15f, z + 0.15f));
        }
    add_bookshelf(m, random, 5.0f, 8.0f);

    // The teacher's desk before the blackboard.
    m.begin_object();
    add_desk(m, 6.0f, 1.4f, 1.0f, 0.4f);
    add_desk_objects(m, random, 6.0f, 1.4f, 1.0f, 0.4f, 4, coarseness);

    // Four rows of four desks with an aisle in the middle (where the pillar stands); chairs behind.
    constexpr float kColumns[4] = {1.8f, 4.0f, 8.0f, 10.2f};
    constexpr float kRows[4] = {3.0f, 4.6f, 6.2f, 7.8f};
    constexpr float kHalfWidth = 0.7f, kHalfDepth = 0.35f;
    for (float row : kRows)
        for (float column : kColumns) {
            const float x = column + random.uniform(-0.1f, 0.1f), z = row + random.uniform(-0.1f, 0.1f);
            m.begin_object();
            add_desk(m, x, z, kHalfWidth, kHalfDepth);
            add_desk_objects(m, random, x, z, kHalfWidth, kHalfDepth, 4, coarseness);
            m.begin_object();
            add_chair(m, x + random.uniform(-0.15f, 0.15f), z + 0.55f + random.uniform(0.0f, 0.15f));
        }

    Scene scene = m.build();
    Camera camera;
    camera.eye = {0.6f, 1.7f, 8.6f};
    camera.at = {7.0f, 0.85f, 2.0f};
    camera.fovy_degrees = 60.0f;
    const bool lite = coarseness != 1;
    return SceneSource{(lite ? "room-lite:" : "room:") + std::to_string(seed), std::move(scene), camera,
                       "furnished classroom 12 x 3.2 x 9 m, seed " + std::to_string(seed) +
                           ": 17 desks with 68 tessellated objects" +
                           (lite ? " (" + std::to_string(coarseness) + "x coarser)" : std::string()) +
                           ", 16 chairs, pillar, bookshelf",
                       m.object_of_triangle()};
}

}  // namespace

SceneSource room(std::uint32_t seed) { return make_room(seed, 1); }
SceneSource room_lite(std::uint32_t seed) { return make_room(seed, kRoomLiteCoarseness); }

}  // namespace beamtrace::scenes
