//! Instancing (USD's scene-graph instances): which prototype prim an instance proxy mesh
//! stands for, and the one place where a layer over the stage can author opinions that every
//! instance of that prototype composes.
//!
//! USD ignores opinions authored on an instance's descendants (instance proxies): an
//! instance's prototype composes only from the arcs of the instance prim. So the `.usda`
//! layer, which sublayers the input and so joins its root layer stack, can change a
//! prototype's mesh for every instance only where the strongest of those arcs targets a
//! prim in the root layer stack: an internal reference (`references = </Prototypes/Crate>`,
//! often to a `class` or an `over`), an inherit or specialize of a class there, or the
//! implied class an inherit inside a referenced layer brings into it. An external reference
//! or payload is the other layer's own opinion, which a layer over the stage cannot change:
//! the mesh is then reported, not written (`usd/write.rs`). Checked with pxr's
//! `Usd.PrimCompositionQuery` and by composing the written layer (tests/usd.rs).

use openusd::{pcp, sdf, usd};
use rustc_hash::FxHashMap;

use crate::source::InstanceSource;

/// The stage's instances, with what was found of each instance prim.
pub(super) struct Instances {
    stage: usd::Stage,
    /// Whether the stage has a prototype at all (else nothing here is computed).
    any: bool,
    /// Per instance prim: the site its prototype's opinions can be authored at, or why none.
    sites: FxHashMap<String, Result<String, String>>,
}

impl Instances {
    pub fn new(stage: &usd::Stage) -> Self {
        Self {
            stage: stage.clone(),
            any: !stage.prototypes().is_empty(),
            sites: FxHashMap::default(),
        }
    }

    /// For a mesh that is an instance proxy: the prototype prim it stands for, its instance,
    /// and where the writer can author its normals for every instance. `None` for a mesh
    /// outside instances.
    ///
    /// # Errors
    ///
    /// openusd's, composing the instance's prim index.
    pub fn source(&mut self, prim: &usd::Prim) -> anyhow::Result<Option<InstanceSource>> {
        if !self.any || !prim.is_instance_proxy()? {
            return Ok(None);
        }
        let Some(prototype) = prim.prim_in_prototype()? else { return Ok(None) };
        let path = prim.path().clone();
        let instance = path.strict_ancestors().find(|p| {
            !p.is_abs_root() && self.stage.prim(p.clone()).is_instance().unwrap_or(false)
        });
        let Some(instance) = instance else { return Ok(None) };
        let key = instance.as_str().to_owned();
        if !self.sites.contains_key(&key) {
            let site = self.instance_site(&instance)?;
            self.sites.insert(key.clone(), site);
        }
        let site = match &self.sites[&key] {
            Ok(at) => {
                let below = &path.as_str()[instance.as_str().len()..];
                Ok(format!("{at}{below}"))
            }
            Err(why) => Err(why.clone()),
        };
        Ok(Some(InstanceSource {
            prototype: prototype.path().as_str().to_owned(),
            instance: key,
            site,
        }))
    }

    /// The site, in the root layer stack, of the strongest arc of `instance` (an instance
    /// prim), or why its prototype's opinions cannot be authored over the stage.
    fn instance_site(&self, instance: &sdf::Path) -> anyhow::Result<Result<String, String>> {
        if self.stage.prim(instance.clone()).is_instance_proxy()? {
            return Ok(Err(format!(
                "its instance <{}> is itself inside an instance (nested instancing)",
                instance.as_str()
            )));
        }
        let graph = self.stage.prim_index(instance.clone()).graph()?;
        let mut nodes = graph.all_nodes();
        let Some(root) = nodes.clone().find(|n| n.arc() == pcp::ArcType::Root) else {
            return Ok(Err("its instance has no composition graph".to_owned()));
        };
        let root_stack = self.stage.node_layer_stack(root);
        let Some(strongest) = nodes.find(|n| n.arc() != pcp::ArcType::Root) else {
            return Ok(Err("its instance has no composition arc".to_owned()));
        };
        let at = strongest.path().as_str().to_owned();
        let arc = match strongest.arc() {
            pcp::ArcType::Reference => "reference",
            pcp::ArcType::Payload => "payload",
            pcp::ArcType::Inherit => "inherit",
            pcp::ArcType::Specialize => "specialize",
            pcp::ArcType::Variant => "variant",
            pcp::ArcType::Relocate => "relocate",
            pcp::ArcType::Root => "root",
        };
        let layer = self
            .stage
            .layer_identifier(strongest.layer_id())
            .unwrap_or_else(|| "another layer".to_owned());
        let writable = matches!(
            strongest.arc(),
            pcp::ArcType::Reference
                | pcp::ArcType::Payload
                | pcp::ArcType::Inherit
                | pcp::ArcType::Specialize
        ) && !at.contains('{');
        if writable && self.stage.node_layer_stack(strongest) == root_stack {
            return Ok(Ok(at));
        }
        Ok(Err(format!(
            "its instance <{}> gets its prototype by a {arc} to <{at}> in @{layer}@, outside the stage's root layer stack, which a layer over the stage cannot change",
            instance.as_str()
        )))
    }

    /// For a mesh outside instances, where the stage has instances: the paths of the sites
    /// in the root layer stack its opinions come from (its own path among them). An over
    /// authored at one of them changes the mesh too.
    ///
    /// # Errors
    ///
    /// openusd's, composing the mesh's prim index.
    pub fn root_sites(&self, path: &sdf::Path) -> anyhow::Result<Vec<String>> {
        if !self.any {
            return Ok(Vec::new());
        }
        let graph = self.stage.prim_index(path.clone()).graph()?;
        let nodes = graph.all_nodes();
        let Some(root) = nodes.clone().find(|n| n.arc() == pcp::ArcType::Root) else {
            return Ok(Vec::new());
        };
        let root_stack = self.stage.node_layer_stack(root);
        Ok(nodes
            .filter(|n| self.stage.node_layer_stack(n) == root_stack)
            .map(|n| n.path().as_str().to_owned())
            .collect())
    }
}
