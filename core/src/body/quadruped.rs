//! The built-in bodies: procedural low-poly quadrupeds in the spirit of the
//! growth paper's "perfect cylindrical horse" (Sec. 5, Fig. 1), so the
//! presets need no files.
//!
//! Each is 18 cylinders — torso (the root), neck, head, two ears, tail and
//! three per leg (forearm or gaskin, cannon, pastern with the hoof) — and
//! eight tubes: the spine (rump to muzzle), four legs, the tail and two
//! ears, generated vertex by vertex. Model space: x forward, y up, z to the
//! animal's left, the ground at y = 0; the horse in inches at 60 months,
//! the cow in centimetres at 36 months (the last age of each table, so a
//! measured feature's model length is the table's value there). Which
//! table column drives which cylinder is documented in `docs/body.md`.

use super::cylinder::{Anchor, Cylinder, Drive, Feature};
use super::mesh::{Mesh, Station, Tube};
use super::table::{cow, horse};
use super::{BodyModel, Label};
use crate::fx::{Angle, Fx};

/// Tenths of a unit.
const fn t(v: i32) -> Fx {
    Fx::from_ratio(v, 10)
}

/// A model point in tenths of a unit.
const fn at(x: i32, y: i32, z: i32) -> [Fx; 3] {
    [t(x), t(y), t(z)]
}

/// A feature between two model points.
const fn feature(from: [Fx; 3], to: [Fx; 3], drive: Drive) -> Feature {
    Feature {
        from,
        to,
        anchor: Anchor::Model,
        drive,
    }
}

/// A lateral (along z) feature of length `width` centred on `c`.
const fn lateral(c: [Fx; 3], width: Fx, drive: Drive) -> Feature {
    let half = width.to_bits() / 2;
    feature(
        [c[0], c[1], Fx::from_bits(c[2].to_bits() - half)],
        [
            c[0],
            c[1],
            Fx::from_bits(c[2].to_bits() - half + width.to_bits()),
        ],
        drive,
    )
}

const fn cylinder(
    name: &str,
    parent: Option<u8>,
    base: [Fx; 3],
    tip: [Fx; 3],
    radius: Fx,
    features: [Feature; 2],
) -> Cylinder {
    Cylinder {
        name: Label::new(name),
        parent,
        base,
        tip,
        radius,
        roll: Angle::ZERO,
        features,
    }
}

const fn flip(p: [Fx; 3]) -> [Fx; 3] {
    [p[0], p[1], Fx::from_bits(-p[2].to_bits())]
}

const fn flip_feature(f: Feature) -> Feature {
    Feature {
        from: flip(f.from),
        to: flip(f.to),
        ..f
    }
}

/// The right-hand twin of a left-side cylinder (z mirrored).
const fn mirror(c: Cylinder, name: &str, parent: Option<u8>) -> Cylinder {
    Cylinder {
        name: Label::new(name),
        parent,
        base: flip(c.base),
        tip: flip(c.tip),
        features: [flip_feature(c.features[0]), flip_feature(c.features[1])],
        ..c
    }
}

const fn station(x: i32, y: i32, z: i32, height: i32, width: i32) -> Station {
    Station {
        centre: at(x, y, z),
        height: t(height),
        width: t(width),
    }
}

/// Rings in the midplane, z = 0 (a tube's own `z` moves a leg or an ear
/// to its side).
const fn rings<const N: usize>(stations: [(i32, i32, i32, i32); N]) -> [Station; N] {
    let mut out = [station(0, 0, 0, 0, 0); N];
    let mut i = 0;
    while i < N {
        let (x, y, h, w) = stations[i];
        out[i] = station(x, y, 0, h, w);
        i += 1;
    }
    out
}

/// A tube of `stations` moved to `z`.
const fn tube(stations: &'static [Station], z: i32, sides: u8, rounded: bool) -> Tube<'static> {
    Tube {
        stations,
        z: t(z),
        sides,
        rounded,
    }
}

// ---------------------------------------------------------------- horse --

/// Cannon-bone diameter at 60 months (Table 1), the model's bone.
const HORSE_CANNON: Fx = Fx::from_ratio(251, 100);

const fn horse_left_fore() -> [Cylinder; 3] {
    let z = 60;
    // Elbow 35.8 in above the ground, knee at 19.8, fetlock at 6.8.
    let elbow_to_ground = feature(
        at(200, 358, z),
        at(200, 0, z),
        Drive::Measured(horse::ELBOW_TO_GROUND),
    );
    [
        cylinder(
            "l-fore-forearm",
            Some(0),
            at(200, 358, z),
            at(200, 168, z),
            t(35),
            [
                elbow_to_ground,
                lateral(
                    at(200, 280, z),
                    t(50),
                    Drive::Follows(horse::CANNON_DIAMETER),
                ),
            ],
        ),
        cylinder(
            "l-fore-cannon",
            Some(6),
            at(200, 198, z),
            at(200, 40, z),
            t(25),
            [
                elbow_to_ground,
                lateral(
                    at(200, 130, z),
                    HORSE_CANNON,
                    Drive::Measured(horse::CANNON_DIAMETER),
                ),
            ],
        ),
        cylinder(
            "l-fore-pastern",
            Some(7),
            at(200, 68, z),
            at(217, -10, z),
            t(30),
            [
                elbow_to_ground,
                lateral(
                    at(207, 34, z),
                    t(30),
                    Drive::Follows(horse::CANNON_DIAMETER),
                ),
            ],
        ),
    ]
}

const fn horse_left_hind() -> [Cylinder; 3] {
    let z = 55;
    // Stifle, hock 23.3 in above the ground (the table's hind leg), fetlock.
    let hock_to_ground = feature(
        at(-270, 233, z),
        at(-270, 0, z),
        Drive::Measured(horse::HIND_LEG),
    );
    [
        cylinder(
            "l-hind-gaskin",
            Some(0),
            at(-200, 400, z),
            at(-280, 210, z),
            t(50),
            [
                feature(
                    at(-200, 400, z),
                    at(-270, 233, z),
                    Drive::Follows(horse::HIND_LEG),
                ),
                lateral(
                    at(-235, 320, z),
                    t(60),
                    Drive::Follows(horse::CANNON_DIAMETER),
                ),
            ],
        ),
        cylinder(
            "l-hind-cannon",
            Some(12),
            at(-270, 233, z),
            at(-270, 45, z),
            t(25),
            [
                hock_to_ground,
                lateral(
                    at(-270, 150, z),
                    t(26),
                    Drive::Follows(horse::CANNON_DIAMETER),
                ),
            ],
        ),
        cylinder(
            "l-hind-pastern",
            Some(13),
            at(-270, 73, z),
            at(-253, -10, z),
            t(30),
            [
                hock_to_ground,
                lateral(
                    at(-262, 36, z),
                    t(30),
                    Drive::Follows(horse::CANNON_DIAMETER),
                ),
            ],
        ),
    ]
}

const HORSE_LF: [Cylinder; 3] = horse_left_fore();
const HORSE_LH: [Cylinder; 3] = horse_left_hind();

/// The horse's 18 cylinders, root first (inches, 60 months).
pub static HORSE_CYLINDERS: [Cylinder; 18] = [
    cylinder(
        "torso",
        None,
        at(-345, 475, 0),
        at(330, 475, 0),
        t(150),
        [
            feature(
                at(-300, 475, 0),
                at(300, 475, 0),
                Drive::Follows(horse::ELBOW_TO_GROUND),
            ),
            feature(
                at(0, 345, 0),
                at(0, 605, 0),
                Drive::Follows(horse::CANNON_DIAMETER),
            ),
        ],
    ),
    cylinder(
        "neck",
        Some(0),
        at(220, 520, 0),
        at(468, 768, 0),
        t(90),
        [
            feature(
                at(220, 520, 0),
                at(440, 740, 0),
                Drive::Follows(horse::ELBOW_TO_GROUND),
            ),
            lateral(
                at(330, 630, 0),
                t(110),
                Drive::Follows(horse::CANNON_DIAMETER),
            ),
        ],
    ),
    cylinder(
        "head",
        Some(1),
        at(440, 740, 0),
        at(570, 525, 0),
        t(70),
        [
            feature(
                at(440, 740, 0),
                at(560, 540, 0),
                Drive::Follows(horse::HEAD_WIDTH),
            ),
            lateral(at(500, 650, 0), t(88), Drive::Measured(horse::HEAD_WIDTH)),
        ],
    ),
    cylinder(
        "l-ear",
        Some(2),
        at(430, 745, 25),
        at(412, 845, 25),
        t(18),
        [
            feature(
                at(430, 745, 25),
                at(412, 845, 25),
                Drive::Follows(horse::HEAD_WIDTH),
            ),
            lateral(at(425, 770, 25), t(20), Drive::Follows(horse::HEAD_WIDTH)),
        ],
    ),
    cylinder(
        "r-ear",
        Some(2),
        at(430, 745, -25),
        at(412, 845, -25),
        t(18),
        [
            feature(
                at(430, 745, -25),
                at(412, 845, -25),
                Drive::Follows(horse::HEAD_WIDTH),
            ),
            lateral(at(425, 770, -25), t(20), Drive::Follows(horse::HEAD_WIDTH)),
        ],
    ),
    cylinder(
        "tail",
        Some(0),
        at(-300, 540, 0),
        at(-385, 260, 0),
        t(45),
        [
            feature(
                at(-300, 540, 0),
                at(-385, 260, 0),
                Drive::Follows(horse::HIND_LEG),
            ),
            lateral(
                at(-340, 400, 0),
                t(50),
                Drive::Follows(horse::CANNON_DIAMETER),
            ),
        ],
    ),
    HORSE_LF[0],
    HORSE_LF[1],
    HORSE_LF[2],
    mirror(HORSE_LF[0], "r-fore-forearm", Some(0)),
    mirror(HORSE_LF[1], "r-fore-cannon", Some(9)),
    mirror(HORSE_LF[2], "r-fore-pastern", Some(10)),
    HORSE_LH[0],
    HORSE_LH[1],
    HORSE_LH[2],
    mirror(HORSE_LH[0], "r-hind-gaskin", Some(0)),
    mirror(HORSE_LH[1], "r-hind-cannon", Some(15)),
    mirror(HORSE_LH[2], "r-hind-pastern", Some(16)),
];

/// Rump to muzzle: (x, y, half height, half width), tenths of an inch.
static HORSE_SPINE: [Station; 16] = rings([
    (-305, 490, 70, 55),
    (-285, 500, 110, 85),
    (-220, 495, 125, 100),
    (-120, 480, 125, 105),
    (-20, 475, 128, 108),
    (80, 475, 128, 105),
    (170, 485, 125, 95),
    (235, 515, 105, 75),
    (295, 585, 75, 50),
    (350, 650, 60, 40),
    (400, 705, 50, 35),
    (440, 740, 48, 36),
    (475, 705, 45, 44),
    (510, 645, 38, 36),
    (540, 590, 30, 28),
    (560, 548, 26, 24),
]);

/// Elbow or stifle to sole; the last two rings one above the other: a
/// flat sole on the ground.
const HORSE_FORE: [(i32, i32, i32, i32); 11] = [
    (200, 440, 45, 38),
    (200, 370, 42, 32),
    (200, 300, 33, 26),
    (200, 235, 27, 22),
    (200, 200, 25, 21),
    (200, 160, 17, 15),
    (200, 100, 15, 13),
    (202, 70, 18, 15),
    (208, 35, 14, 13),
    (215, 8, 21, 19),
    (215, 0, 22, 20),
];
/// Elbow or stifle to sole; the last two rings one above the other: a
/// flat sole on the ground.
const HORSE_HIND: [(i32, i32, i32, i32); 11] = [
    (-215, 470, 60, 45),
    (-205, 400, 55, 40),
    (-225, 340, 42, 30),
    (-250, 285, 32, 24),
    (-268, 240, 27, 22),
    (-270, 190, 18, 15),
    (-270, 120, 15, 13),
    (-268, 75, 18, 15),
    (-262, 35, 14, 13),
    (-255, 8, 21, 19),
    (-255, 0, 22, 20),
];
const HORSE_TAIL: [(i32, i32, i32, i32); 5] = [
    (-300, 545, 25, 25),
    (-325, 480, 32, 28),
    (-345, 410, 30, 25),
    (-362, 340, 25, 20),
    (-375, 280, 15, 12),
];
const HORSE_EAR: [(i32, i32, i32, i32); 3] =
    [(430, 750, 14, 10), (424, 795, 12, 8), (416, 838, 5, 4)];

static HORSE_FORE_RINGS: [Station; 11] = rings(HORSE_FORE);
static HORSE_HIND_RINGS: [Station; 11] = rings(HORSE_HIND);
static HORSE_TAIL_RINGS: [Station; 5] = rings(HORSE_TAIL);
static HORSE_EAR_RINGS: [Station; 3] = rings(HORSE_EAR);

/// The horse's tubes: far side first, so a painter draws the near side last.
static HORSE_TUBES: [Tube<'static>; 8] = [
    tube(&HORSE_HIND_RINGS, -55, 8, false),
    tube(&HORSE_FORE_RINGS, -60, 8, false),
    tube(&HORSE_EAR_RINGS, -25, 4, true),
    tube(&HORSE_SPINE, 0, 10, true),
    tube(&HORSE_TAIL_RINGS, 0, 6, true),
    tube(&HORSE_EAR_RINGS, 25, 4, true),
    tube(&HORSE_HIND_RINGS, 55, 8, false),
    tube(&HORSE_FORE_RINGS, 60, 8, false),
];

/// The built-in quarter horse: inches, modelled at 60 months.
pub static HORSE: BodyModel<'static> = BodyModel {
    cylinders: &HORSE_CYLINDERS,
    mesh: Mesh::Tubes(&HORSE_TUBES),
    model_age: Fx::from_int(60),
};

// ------------------------------------------------------------------ cow --

const fn cow_left_fore() -> [Cylinder; 3] {
    let z = 170;
    // Elbow 65 cm above the ground: the withers height (Table 2) less the
    // trunk above the elbow, which grows with the chest depth.
    let elbow_to_ground = feature(
        at(330, 650, z),
        at(330, 0, z),
        Drive::Below {
            column: cow::WITHERS_HEIGHT,
            above: cow::CHEST_DEPTH,
        },
    );
    let girth = Drive::Follows(cow::CHEST_DEPTH);
    [
        cylinder(
            "l-fore-forearm",
            Some(0),
            at(330, 650, z),
            at(330, 300, z),
            t(100),
            [elbow_to_ground, lateral(at(330, 500, z), t(120), girth)],
        ),
        cylinder(
            "l-fore-cannon",
            Some(6),
            at(330, 350, z),
            at(330, 80, z),
            t(65),
            [elbow_to_ground, lateral(at(330, 220, z), t(70), girth)],
        ),
        cylinder(
            "l-fore-pastern",
            Some(7),
            at(330, 120, z),
            at(361, -15, z),
            t(65),
            [elbow_to_ground, lateral(at(345, 60, z), t(70), girth)],
        ),
    ]
}

const fn cow_left_hind() -> [Cylinder; 3] {
    let z = 160;
    // The stifle's height, 72 cm, down to the ground below the hock: the
    // croup height (Table 2) less the trunk above the stifle, which grows
    // with the chest depth.
    let stifle_to_ground = feature(
        at(-680, 720, z),
        at(-680, 0, z),
        Drive::Below {
            column: cow::CROUP_HEIGHT,
            above: cow::CHEST_DEPTH,
        },
    );
    let girth = Drive::Follows(cow::CHEST_DEPTH);
    [
        cylinder(
            "l-hind-gaskin",
            Some(0),
            at(-560, 720, z),
            at(-700, 405, z),
            t(110),
            [stifle_to_ground, lateral(at(-620, 580, z), t(150), girth)],
        ),
        cylinder(
            "l-hind-cannon",
            Some(12),
            at(-680, 450, z),
            at(-680, 80, z),
            t(65),
            [stifle_to_ground, lateral(at(-680, 250, z), t(70), girth)],
        ),
        cylinder(
            "l-hind-pastern",
            Some(13),
            at(-680, 120, z),
            at(-652, -15, z),
            t(65),
            [stifle_to_ground, lateral(at(-668, 60, z), t(70), girth)],
        ),
    ]
}

const COW_LF: [Cylinder; 3] = cow_left_fore();
const COW_LH: [Cylinder; 3] = cow_left_hind();

/// Poll-to-muzzle at 36 months (Table 2) as an oblique pair (38.6, −35.0):
/// 52.105 cm, 11° off the head's axis, so the head's 2×2 system couples L
/// and R.
const COW_POLL: [Fx; 3] = at(830, 1050, 0);
const COW_MUZZLE: [Fx; 3] = at(1216, 700, 0);

/// The cow's 18 cylinders, root first (centimetres, 36 months).
pub static COW_CYLINDERS: [Cylinder; 18] = [
    cylinder(
        "torso",
        None,
        at(-960, 960, 0),
        at(880, 960, 0),
        t(400),
        [
            feature(
                at(-800, 960, 0),
                at(800, 960, 0),
                Drive::Follows(cow::WITHERS_HEIGHT),
            ),
            // Chest depth at the withers: 131.7 down to 63.3 cm.
            feature(
                at(420, 633, 0),
                at(420, 1317, 0),
                Drive::Measured(cow::CHEST_DEPTH),
            ),
        ],
    ),
    cylinder(
        "neck",
        Some(0),
        at(540, 955, 0),
        at(910, 1020, 0),
        t(260),
        [
            feature(
                at(540, 955, 0),
                at(850, 1010, 0),
                Drive::Follows(cow::WITHERS_HEIGHT),
            ),
            lateral(at(700, 980, 0), t(300), Drive::Follows(cow::CHEST_DEPTH)),
        ],
    ),
    cylinder(
        "head",
        Some(1),
        at(850, 1010, 0),
        at(1180, 570, 0),
        t(140),
        [
            feature(COW_POLL, COW_MUZZLE, Drive::Measured(cow::POLL_TO_MUZZLE)),
            lateral(
                at(900, 960, 0),
                t(197),
                Drive::Measured(cow::FOREHEAD_WIDTH),
            ),
        ],
    ),
    cylinder(
        "l-ear",
        Some(2),
        at(830, 1010, 90),
        at(790, 1100, 90),
        t(40),
        [
            feature(
                at(830, 1010, 90),
                at(790, 1100, 90),
                Drive::Follows(cow::FOREHEAD_WIDTH),
            ),
            lateral(
                at(815, 1040, 90),
                t(50),
                Drive::Follows(cow::FOREHEAD_WIDTH),
            ),
        ],
    ),
    cylinder(
        "r-ear",
        Some(2),
        at(830, 1010, -90),
        at(790, 1100, -90),
        t(40),
        [
            feature(
                at(830, 1010, -90),
                at(790, 1100, -90),
                Drive::Follows(cow::FOREHEAD_WIDTH),
            ),
            lateral(
                at(815, 1040, -90),
                t(50),
                Drive::Follows(cow::FOREHEAD_WIDTH),
            ),
        ],
    ),
    cylinder(
        "tail",
        Some(0),
        at(-820, 1080, 0),
        at(-885, 430, 0),
        t(60),
        [
            feature(
                at(-820, 1080, 0),
                at(-885, 430, 0),
                Drive::Follows(cow::CROUP_HEIGHT),
            ),
            lateral(at(-850, 800, 0), t(40), Drive::Follows(cow::CHEST_DEPTH)),
        ],
    ),
    COW_LF[0],
    COW_LF[1],
    COW_LF[2],
    mirror(COW_LF[0], "r-fore-forearm", Some(0)),
    mirror(COW_LF[1], "r-fore-cannon", Some(9)),
    mirror(COW_LF[2], "r-fore-pastern", Some(10)),
    COW_LH[0],
    COW_LH[1],
    COW_LH[2],
    mirror(COW_LH[0], "r-hind-gaskin", Some(0)),
    mirror(COW_LH[1], "r-hind-cannon", Some(15)),
    mirror(COW_LH[2], "r-hind-pastern", Some(16)),
];

/// Rump to muzzle, tenths of a centimetre.
static COW_SPINE: [Station; 15] = rings([
    (-830, 1030, 200, 170),
    (-790, 1010, 300, 250),
    (-650, 990, 345, 290),
    (-400, 960, 355, 320),
    (-100, 950, 360, 330),
    (200, 960, 350, 300),
    (420, 975, 342, 270),
    (580, 960, 280, 200),
    (700, 970, 200, 150),
    (790, 990, 160, 120),
    (850, 1005, 140, 100),
    (900, 960, 115, 99),
    (990, 850, 95, 85),
    (1080, 730, 80, 70),
    (1140, 640, 70, 65),
]);

/// Elbow or stifle to sole; the last two rings one above the other: a
/// flat sole on the ground.
const COW_FORE: [(i32, i32, i32, i32); 11] = [
    (330, 800, 110, 90),
    (330, 700, 100, 80),
    (330, 560, 80, 62),
    (330, 420, 62, 50),
    (330, 360, 58, 48),
    (330, 300, 45, 38),
    (330, 200, 40, 34),
    (333, 125, 45, 38),
    (345, 60, 40, 36),
    (358, 15, 50, 45),
    (358, 0, 52, 47),
];
/// Elbow or stifle to sole; the last two rings one above the other: a
/// flat sole on the ground.
const COW_HIND: [(i32, i32, i32, i32); 11] = [
    (-600, 880, 140, 100),
    (-560, 730, 120, 90),
    (-600, 610, 95, 70),
    (-650, 520, 70, 55),
    (-678, 455, 62, 50),
    (-680, 380, 45, 38),
    (-680, 230, 40, 34),
    (-678, 125, 45, 38),
    (-668, 60, 40, 36),
    (-658, 15, 50, 45),
    (-658, 0, 52, 47),
];
const COW_TAIL: [(i32, i32, i32, i32); 5] = [
    (-820, 1080, 40, 40),
    (-850, 950, 30, 30),
    (-865, 800, 22, 22),
    (-875, 620, 20, 20),
    (-880, 480, 35, 35),
];
const COW_EAR: [(i32, i32, i32, i32); 3] =
    [(830, 1020, 35, 20), (815, 1055, 25, 15), (795, 1090, 10, 6)];

static COW_FORE_RINGS: [Station; 11] = rings(COW_FORE);
static COW_HIND_RINGS: [Station; 11] = rings(COW_HIND);
static COW_TAIL_RINGS: [Station; 5] = rings(COW_TAIL);
static COW_EAR_RINGS: [Station; 3] = rings(COW_EAR);

static COW_TUBES: [Tube<'static>; 8] = [
    tube(&COW_HIND_RINGS, -160, 8, false),
    tube(&COW_FORE_RINGS, -170, 8, false),
    tube(&COW_EAR_RINGS, -90, 4, true),
    tube(&COW_SPINE, 0, 10, true),
    tube(&COW_TAIL_RINGS, 0, 6, true),
    tube(&COW_EAR_RINGS, 90, 4, true),
    tube(&COW_HIND_RINGS, 160, 8, false),
    tube(&COW_FORE_RINGS, 170, 8, false),
];

/// The built-in Holstein: centimetres, modelled at 36 months.
pub static COW: BodyModel<'static> = BodyModel {
    cylinders: &COW_CYLINDERS,
    mesh: Mesh::Tubes(&COW_TUBES),
    model_age: Fx::from_int(36),
};
