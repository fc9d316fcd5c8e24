"""Scenes shipped to machines that do not share this one's file system.

A `SceneBundle` holds a scene file and every file its load reads (included meshes, MTL
libraries, glTF buffers and images, textures: prism's loader lists them), as bytes under
paths relative to their common folder. A Dask client scatters one bundle to every worker
once; a worker writes it into a folder of its own, named by the bundle's digest, and loads
the scene from there. A scene on a file system every worker mounts at the same path can
be declared `shared` instead, and then only its path travels. Built-in scenes travel by
name.
"""

import hashlib
import os
import tempfile
import threading
from dataclasses import dataclass, field

from . import _prism


@dataclass(frozen=True)
class SceneBundle:
    """A scene as it travels: `scene` is "builtin:NAME", a shared path, or the path of
    the scene file among `files` (relative path -> bytes); `digest` names the content."""

    scene: str
    files: dict = field(default_factory=dict, repr=False)
    digest: str = ""
    #: The image size the scene asks for, (width, height).
    size: tuple = (0, 0)

    @classmethod
    def of(cls, scene, shared=False):
        """The bundle of a scene file (its files read here, now) or "builtin:NAME"; with
        `shared`, only the path, which every worker must be able to open."""
        scene = os.fspath(scene)
        if scene.startswith("builtin:"):
            # An unknown name is refused here, once, not by every worker.
            size = _prism.builtin(scene[len("builtin:") :]).size
            return cls(scene=scene, digest=_digest(scene.encode(), {}), size=size)
        listed, size = _prism.scene_files(scene)
        paths = [os.path.abspath(p) for p in listed]
        if shared:
            path = os.path.abspath(scene)
            return cls(scene=path, digest=_digest(path.encode(), {}), size=size)
        root = os.path.commonpath([os.path.dirname(p) for p in paths])
        files = {}
        for p in paths:
            with open(p, "rb") as f:
                files[os.path.relpath(p, root).replace(os.sep, "/")] = f.read()
        name = os.path.relpath(os.path.abspath(scene), root).replace(os.sep, "/")
        return cls(scene=name, files=files, digest=_digest(name.encode(), files), size=size)

    @property
    def bytes(self):
        """Bytes of the files shipped."""
        return sum(len(b) for b in self.files.values())

    def path(self):
        """Where this process loads the scene from: the built-in's name, the shared path,
        or the scene file in this machine's copy of the bundle (written on first use)."""
        if not self.files:
            return self.scene
        folder = os.path.join(tempfile.gettempdir(), "prism-scenes", self.digest)
        with _writing:
            for rel, data in self.files.items():
                target = os.path.join(folder, *rel.split("/"))
                if os.path.isfile(target) and os.path.getsize(target) == len(data):
                    continue
                os.makedirs(os.path.dirname(target), exist_ok=True)
                # Several worker processes of one machine may write the same bundle: each
                # writes a file of its own and renames it, so none reads a partial file.
                temporary = f"{target}.{os.getpid()}.{threading.get_ident()}.part"
                with open(temporary, "wb") as f:
                    f.write(data)
                os.replace(temporary, target)
        return os.path.join(folder, *self.scene.split("/"))

    def load(self):
        """The scene, loaded in this process."""
        from . import builtin, load

        where = self.path()
        if where.startswith("builtin:"):
            return builtin(where[len("builtin:") :])
        return load(where)


_writing = threading.Lock()


def _digest(name, files):
    h = hashlib.sha256(name)
    for rel in sorted(files):
        h.update(b"\0" + rel.encode() + b"\0")
        h.update(hashlib.sha256(files[rel]).digest())
    return h.hexdigest()[:24]
