use super::super::builtin::tests::assert_winding_matches_normals;
use super::*;
use crate::geom::Aabb;

fn small(seed: u64) -> Scene {
    build_city("small".into(), &CityParams::small(seed))
}

/// `(i, j)` of a name `block_i_j/...`.
fn block_of(name: &str) -> Option<(u32, u32)> {
    let (block, _) = name.strip_prefix("block_")?.split_once('/')?;
    let (i, j) = block.split_once('_')?;
    Some((i.parse().ok()?, j.parse().ok()?))
}

fn footprint_inside(aabb: &Aabb, rect: &RectXz) -> bool {
    let eps = 1e-3;
    aabb.min.x >= rect.min.x - eps
        && aabb.min.z >= rect.min.y - eps
        && aabb.max.x <= rect.max.x + eps
        && aabb.max.z <= rect.max.y + eps
}

fn is_building(name: &str) -> bool {
    name.contains("/building_") || name.starts_with("tower_")
}

#[test]
fn same_seed_builds_the_same_city() {
    let (a, b) = (small(42), small(42));
    assert_eq!(a.instances.len(), b.instances.len());
    assert_eq!(a.meshes.len(), b.meshes.len());
    assert_eq!(a.triangle_count(), b.triangle_count());
    for (x, y) in a.instances.iter().zip(&b.instances) {
        assert_eq!(x.name, y.name);
        assert_eq!(x.world_from_local, y.world_from_local);
        assert_eq!(
            x.base_color.map(f32::to_bits),
            y.base_color.map(f32::to_bits)
        );
        assert_eq!(x.mesh, y.mesh);
    }
}

#[test]
fn different_seeds_build_different_cities() {
    let (a, b) = (small(1), small(2));
    let differs = a.instances.len() != b.instances.len()
        || a.instances
            .iter()
            .zip(&b.instances)
            .any(|(x, y)| x.name != y.name || x.world_from_local != y.world_from_local);
    assert!(differs);
}

#[test]
fn full_city_has_the_target_size() {
    let scene = build_city("city".into(), &CityParams::full(0));
    let (objects, triangles) = (scene.instances.len(), scene.triangle_count());
    let count = |prefix: &str| {
        scene
            .instances
            .iter()
            .filter(|i| i.name.contains(prefix))
            .count()
    };
    println!(
        "city: {objects} objects, {triangles} triangles, {} meshes; {} buildings, {} towers, {} trees, {} cars",
        scene.meshes.len(),
        count("/building_"),
        count("tower_"),
        count("/tree_"),
        count("car_"),
    );
    let small = small(0);
    println!(
        "city-small: {} objects, {} triangles",
        small.instances.len(),
        small.triangle_count()
    );
    assert!((7_000..=15_000).contains(&objects), "{objects} objects");
    assert!(
        (700_000..=1_500_000).contains(&triangles),
        "{triangles} triangles"
    );
    assert!(scene.meshes.len() * 100 < objects, "meshes are shared");
    assert_eq!(count("tower_"), 12);
    assert!((100..1_000).contains(&small.instances.len()));
}

#[test]
fn ground_tiles_cover_the_city_without_overlap() {
    let params = CityParams::small(3);
    let scene = build_city("small".into(), &params);
    let tiles: Vec<&Instance> = scene
        .instances
        .iter()
        .filter(|i| i.name.starts_with("ground_"))
        .collect();
    assert_eq!(tiles.len(), 16);
    let ground = params.ground_rect();
    let area: f32 = tiles
        .iter()
        .map(|t| t.aabb_in_world.extent().x * t.aabb_in_world.extent().z)
        .sum();
    assert!((area / (ground.size().x * ground.size().y) - 1.0).abs() < 1e-4);
    for tile in tiles {
        assert!(footprint_inside(&tile.aabb_in_world, &ground));
        assert!(tile.casts_shadow && tile.receives_shadow && tile.mobility == Mobility::Static);
    }
    assert!((ground.center()).length() < 1e-3, "centred on the origin");
}

#[test]
fn cars_are_dynamic_and_on_the_ground() {
    let params = CityParams::small(7);
    let scene = build_city("small".into(), &params);
    let ground = params.ground_rect();
    let cars: Vec<&Instance> = scene
        .instances
        .iter()
        .filter(|i| i.name.starts_with("car_"))
        .collect();
    assert!(cars.len() > 50);
    for car in &cars {
        assert_eq!(car.mobility, Mobility::Dynamic, "{}", car.name);
        assert!(
            footprint_inside(&car.aabb_in_world, &ground),
            "{}",
            car.name
        );
        assert!(car.aabb_in_world.min.y > -1e-3 && car.aabb_in_world.max.y < 3.5);
        // In a street: on no block.
        for j in 0..params.blocks_z {
            for i in 0..params.blocks_x {
                let block = params.block_rect(i, j);
                let a = car.aabb_in_world;
                let overlaps = a.min.x < block.max.x
                    && block.min.x < a.max.x
                    && a.min.z < block.max.y
                    && block.min.y < a.max.z;
                assert!(!overlaps, "{} is on block {i} {j}", car.name);
            }
        }
    }
    let dynamic = scene
        .instances
        .iter()
        .filter(|i| i.mobility == Mobility::Dynamic)
        .count();
    assert_eq!(dynamic, cars.len(), "only cars move");
}

#[test]
fn buildings_and_trees_stay_inside_their_blocks() {
    let params = CityParams::small(11);
    let scene = build_city("small".into(), &params);
    for instance in &scene.instances {
        if let Some((i, j)) = block_of(&instance.name) {
            // The world box of a rotated tree is loose: test the geometry itself.
            let mesh = scene.mesh_of(instance);
            let footprint = Aabb::from_points(
                mesh.positions
                    .iter()
                    .map(|p| instance.world_from_local.transform_point3(*p)),
            );
            let block = params.block_rect(i, j);
            assert!(
                footprint_inside(&footprint, &block),
                "{} leaves its block",
                instance.name
            );
            if instance.name.contains("/building_") {
                let lots = block.shrunk(SIDEWALK_WIDTH_M);
                assert!(
                    footprint_inside(&instance.aabb_in_world, &lots),
                    "{} on the sidewalk",
                    instance.name
                );
            }
        } else if instance.name.starts_with("tower_") {
            let inside_some_block = (0..params.blocks_z)
                .flat_map(|j| (0..params.blocks_x).map(move |i| (i, j)))
                .any(|(i, j)| footprint_inside(&instance.aabb_in_world, &params.block_rect(i, j)));
            assert!(inside_some_block, "{} is in a street", instance.name);
        }
    }
}

#[test]
fn buildings_do_not_overlap() {
    let scene = small(5);
    let boxes: Vec<(&str, Aabb)> = scene
        .instances
        .iter()
        .filter(|i| is_building(&i.name))
        .map(|i| (i.name.as_str(), i.aabb_in_world))
        .collect();
    assert!(boxes.len() > 100);
    for (k, (name_a, a)) in boxes.iter().enumerate() {
        for (name_b, b) in &boxes[k + 1..] {
            let overlap =
                a.min.x < b.max.x && b.min.x < a.max.x && a.min.z < b.max.z && b.min.z < a.max.z;
            assert!(!overlap, "{name_a} overlaps {name_b}");
        }
    }
}

#[test]
fn heights_are_mostly_ten_to_sixty_metres_and_towers_tall() {
    let scene = build_city("city".into(), &CityParams::full(9));
    let heights: Vec<f32> = scene
        .instances
        .iter()
        .filter(|i| i.name.contains("/building_"))
        .map(|i| i.aabb_in_world.extent().y)
        .collect();
    let in_range = heights.iter().filter(|h| (9.0..=61.0).contains(*h)).count();
    assert!(in_range as f32 > 0.9 * heights.len() as f32);
    for tower in scene
        .instances
        .iter()
        .filter(|i| i.name.starts_with("tower_"))
    {
        assert!(
            (100.0..=301.0).contains(&tower.aabb_in_world.max.y),
            "{}",
            tower.name
        );
    }
}

/// Even-odd test of a point against the closed (half width, height) outline of a profile.
fn inside_profile(outline: &[[f32; 2]], point: Vec2) -> bool {
    let mut inside = false;
    for k in 0..outline.len() {
        let ([x0, y0], [x1, y1]) = (outline[k], outline[(k + 1) % outline.len()]);
        if (y0 > point.y) != (y1 > point.y) && point.x < x0 + (point.y - y0) / (y1 - y0) * (x1 - x0)
        {
            inside = !inside;
        }
    }
    inside
}

#[test]
fn building_faces_point_outward() {
    for kind in [
        Proto::LowRise,
        Proto::MidRise,
        Proto::Setback,
        Proto::Plain,
        Proto::Tower,
    ] {
        let profile = building_profile(kind);
        let mut outline = vec![[0.0, 0.0]];
        outline.extend(&profile);
        outline.push([0.0, profile.last().map_or(0.0, |p| p[1])]);
        let mesh = kind.mesh();
        assert!(
            mesh.aabb_in_local
                .min
                .abs_diff_eq(Vec3::new(-0.5, 0.0, -0.5), 1e-6)
        );
        assert!(
            mesh.aabb_in_local
                .max
                .abs_diff_eq(Vec3::new(0.5, 1.0, 0.5), 1e-6)
        );
        // Just behind each face is inside the solid, just in front of it is outside.
        let probe = |p: Vec3| inside_profile(&outline, Vec2::new(p.x.abs().max(p.z.abs()), p.y));
        for tri in mesh.indices.chunks_exact(3) {
            let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| mesh.positions[i as usize]);
            let (centroid, normal) = ((a + b + c) / 3.0, mesh.normals[tri[0] as usize]);
            assert!(
                probe(centroid - normal * 1e-3),
                "{}: face at {centroid} points inward",
                mesh.name
            );
            assert!(
                !probe(centroid + normal * 1e-3),
                "{}: face at {centroid} points inward",
                mesh.name
            );
        }
        assert_winding_matches_normals(&mesh);
    }
}

#[test]
fn prototypes_wind_with_their_normals_and_have_modest_sizes() {
    for proto in Proto::ALL {
        let mesh = proto.mesh();
        assert_winding_matches_normals(&mesh);
        let triangles = mesh.triangle_count();
        println!("{}: {triangles} triangles", mesh.name);
        match proto {
            Proto::LowRise | Proto::MidRise | Proto::Setback => {
                assert!((100..600).contains(&triangles));
            }
            Proto::Sedan | Proto::Suv | Proto::Truck => {
                assert!((100..=300).contains(&triangles));
                assert!(
                    mesh.aabb_in_local.min.y.abs() < 0.02,
                    "wheels on the ground"
                );
            }
            _ => {}
        }
    }
}

#[test]
fn rng_is_deterministic_and_in_range() {
    let (mut a, mut b) = (SplitMix64::new(3), SplitMix64::new(3));
    for _ in 0..1000 {
        assert_eq!(a.next_u64(), b.next_u64());
        let u = a.unit_f32();
        assert!((0.0..1.0).contains(&u));
        assert!(a.below(7) < 7);
        b.unit_f32();
        b.below(7);
    }
    assert_eq!(a.below(0), 0);
    assert_ne!(SplitMix64::new(1).next_u64(), SplitMix64::new(2).next_u64());
}

#[test]
fn cars_drive_along_their_lanes_and_stay_in_the_streets() {
    let params = CityParams::small(3);
    let mut scene = build_city("small".into(), &params);
    let dynamic: Vec<u32> = (0..scene.instances.len() as u32)
        .filter(|&i| scene.instances[i as usize].mobility == Mobility::Dynamic)
        .collect();
    let mut with_motion: Vec<u32> = scene.motions.iter().map(|m| m.instance).collect();
    with_motion.sort_unstable();
    assert_eq!(with_motion, dynamic, "one motion per car");
    let at_start: Vec<Vec3> = dynamic
        .iter()
        .map(|&i| {
            scene.instances[i as usize]
                .world_from_local
                .transform_point3(Vec3::ZERO)
        })
        .collect();

    // Time 0 reproduces the generated layout.
    let moved = scene.animate(0.0);
    assert_eq!(moved.len(), dynamic.len());
    for (k, &i) in dynamic.iter().enumerate() {
        let p = scene.instances[i as usize]
            .world_from_local
            .transform_point3(Vec3::ZERO);
        assert!(
            (p - at_start[k]).length() < 1e-3,
            "car {} moved at time 0",
            scene.instances[i as usize].name
        );
    }
    // Later, cars have moved, along the ground, outside every block; the BVH follows them.
    for time in [0.7, 3.0, 41.0] {
        scene.animate(time);
        let mut moved_count = 0;
        for (k, &i) in dynamic.iter().enumerate() {
            let inst = &scene.instances[i as usize];
            let p = inst.world_from_local.transform_point3(Vec3::ZERO);
            moved_count += usize::from((p - at_start[k]).length() > 1.0);
            assert!(p.y.abs() < 1e-4, "{} left the ground", inst.name);
            for bi in 0..params.blocks_x {
                for bj in 0..params.blocks_z {
                    let block = params.block_rect(bi, bj);
                    let inside = p.x > block.min.x
                        && p.x < block.max.x
                        && p.z > block.min.y
                        && p.z < block.max.y;
                    assert!(
                        !inside,
                        "{} drove into block ({bi}, {bj}) at {time} s",
                        inst.name
                    );
                }
            }
            let mut hits = Vec::new();
            scene.bvh().query_aabb(&inst.aabb_in_world, &mut hits);
            assert!(
                hits.contains(&i),
                "the BVH lost {} after it moved",
                inst.name
            );
        }
        assert!(
            moved_count * 10 > dynamic.len() * 9,
            "only {moved_count} of {} cars moved at {time} s",
            dynamic.len()
        );
    }
}
