"""What MuJoCo does to masses and inertias that Pinocchio's MJCF parser does not, refused with the element
and attribute. MuJoCo (`<compiler>`): a body without `<inertial>` takes the inertia of its geoms
(inertiafromgeom="auto"; "true": always, "false": never), only those of a group within inertiagrouprange,
counting a geom whatever its contype and conaffinity; a mesh's inertia comes from its volume (or shell);
settotalmass scales all masses, boundmass and boundinertia raise small ones, balanceinertia changes
impossible ones. Pinocchio's parser drops the geoms with contype = conaffinity = 0, takes a mesh as mass
1 with unit inertia and reads none of these compiler attributes."""
from __future__ import annotations

import xml.etree.ElementTree as ET

from ..errors import ModelError
from .mjcf_defaults import Defaults


def _compiler(root: ET.Element, owner: str) -> dict[str, str]:
    """The attributes of `<compiler>`, refusing those that change inertias."""
    given = {k: v for c in root.findall("compiler") for k, v in c.attrib.items()}
    unused = {"settotalmass": ("-1",), "boundmass": ("0",), "boundinertia": ("0",),
              "balanceinertia": ("false",)}
    for name, values in unused.items():
        if name in given and given[name].strip() not in values:
            raise ModelError(f"{owner}: <compiler {name}={given[name]!r}> changes the masses or inertias "
                             "and is not read by Pinocchio's parser (remove it and state the inertias)")
    return given


def check_inertias(root: ET.Element, bodies: list, defaults: Defaults, owner: str) -> None:
    """Refuse, for each body whose inertia MuJoCo takes from geoms, what Pinocchio's parser would read
    otherwise (see the module); `bodies`: (body, class, name)."""
    compiler = _compiler(root, owner)
    fromgeom = compiler.get("inertiafromgeom", "auto")
    groups = compiler.get("inertiagrouprange", "0 5")
    if groups.split() != ["0", "5"] and any(b.find("inertial") is None and b.find("geom") is not None
                                             for b, _, _ in bodies):
        raise ModelError(f"{owner}: <compiler inertiagrouprange={groups!r}> is not read by Pinocchio's "
                         "parser (remove it, or give each body with geoms an <inertial>)")
    for body, cls, name in bodies:
        given, geoms = body.find("inertial") is not None, body.findall("geom")
        if geoms and (fromgeom == "true" and given or fromgeom == "false" and not given):
            raise ModelError(f"{owner}: <compiler inertiafromgeom={fromgeom!r}> with body '{name}' "
                             "(Pinocchio's parser takes the geoms' inertia exactly when a body has no "
                             "<inertial>)")
        if given or fromgeom == "false":
            continue
        for k, geom in enumerate(geoms):
            where = f"{owner}: body '{name}': geom '{geom.get('name') or k}'"
            def attribute(name: str, default: str) -> str:
                return defaults.get(geom, name, cls) or default

            if attribute("type", "sphere") == "mesh" or geom.get("mesh"):
                raise ModelError(f"{where}: a mesh's inertia is not read (Pinocchio's parser would take "
                                 "mass 1 and unit inertia): give the body an <inertial>")
            if attribute("contype", "1") == "0" and attribute("conaffinity", "1") == "0":
                raise ModelError(f"{where}: contype=0 and conaffinity=0; MuJoCo counts its mass, "
                                 "Pinocchio's parser drops it: give the body an <inertial>")
            if attribute("shellinertia", "false") == "true":
                raise ModelError(f"{where}: shellinertia is not read by Pinocchio's parser: give the body "
                                 "an <inertial>")
