//! The node hierarchy of the scene to show: which meshes, cameras and lights it places,
//! and where. Walked depth-first in file order with an explicit stack, so a deep
//! hierarchy cannot overflow the stack and a cycle is reported instead of looping.

use super::transform;
use glam::DAffine3;
use gltf::json::Root;

/// What the scene's nodes place in the world.
#[derive(Default)]
pub(super) struct Placed {
    /// Node index, mesh index and world transform, one entry per node that has a mesh.
    pub meshes: Vec<(usize, usize, DAffine3)>,
    /// The first camera met in the walk, with its world transform.
    pub camera: Option<(usize, DAffine3)>,
    /// KHR_lights_punctual light index and world transform.
    pub lights: Vec<(usize, DAffine3)>,
}

/// The nodes to start from: the file's `scene`, else its first scene, else (a file
/// without scenes) every node that is no other node's child.
fn roots(root: &Root) -> Result<Vec<usize>, String> {
    let scene = match root.scene {
        Some(s) => Some(root.scenes.get(s.value()).ok_or_else(|| {
            format!(
                "the default scene {} does not exist (the file has {} scenes)",
                s.value(),
                root.scenes.len()
            )
        })?),
        None => root.scenes.first(),
    };
    if let Some(scene) = scene {
        return Ok(scene.nodes.iter().map(|n| n.value()).collect());
    }
    let mut is_child = vec![false; root.nodes.len()];
    for child in root.nodes.iter().flat_map(|n| n.children.iter().flatten()) {
        if let Some(flag) = is_child.get_mut(child.value()) {
            *flag = true;
        }
    }
    Ok((0..root.nodes.len()).filter(|&i| !is_child[i]).collect())
}

pub(super) fn walk(root: &Root) -> Result<Placed, String> {
    let mut placed = Placed::default();
    let mut visited = vec![false; root.nodes.len()];
    let mut stack: Vec<(usize, DAffine3)> = roots(root)?
        .into_iter()
        .rev()
        .map(|n| (n, DAffine3::IDENTITY))
        .collect();
    while let Some((index, parent)) = stack.pop() {
        let node = root.nodes.get(index).ok_or_else(|| {
            format!(
                "node {index} does not exist (the file has {} nodes)",
                root.nodes.len()
            )
        })?;
        if std::mem::replace(&mut visited[index], true) {
            return Err(format!(
                "node {index} is reached twice (a cycle, or a node with two parents); glTF \
                 nodes must form trees"
            ));
        }
        let world = parent * transform::local(node).map_err(|e| format!("node {index}: {e}"))?;
        if let Some(mesh) = node.mesh {
            placed.meshes.push((index, mesh.value(), world));
        }
        if let Some(camera) = node.camera {
            placed.camera.get_or_insert((camera.value(), world));
        }
        if let Some(light) = node
            .extensions
            .as_ref()
            .and_then(|e| e.khr_lights_punctual.as_ref())
        {
            placed.lights.push((light.light.value(), world));
        }
        for child in node.children.iter().flatten().rev() {
            stack.push((child.value(), world));
        }
    }
    Ok(placed)
}
