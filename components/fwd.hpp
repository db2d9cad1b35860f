#pragma once

namespace ikebana::components {

struct Flower;
struct Part;
struct ActiveCollider;
struct PassiveCollider;
struct InactiveCollider;
struct StemPoints;
struct StemRestShape;
struct StemSprings;
struct StemClamp;
struct StemFrame;
struct StemFork;
struct Twigs;
struct Kenzan;
struct HandCube;
struct Collider;
struct Contacts;
struct PhysicsSettings;
struct WorldEnergy;

} // namespace ikebana::components
