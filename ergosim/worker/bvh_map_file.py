"""Joint-name maps for BVH skeletons that are not recognised, as a TOML file (``ergosim replay --map``).

One key per role of :data:`ergosim.worker.bvh_mapping.ROLES`, the value the BVH joint name that plays it;
roles left out are detected as usual (docs/bvh.md). A Biovision-style skeleton, for example::

    # joint names of a Biovision-style export: role = "BVH joint name"
    right_clavicle = "RightCollar"
    right_upper_arm = "RightShoulder"
    right_forearm = "RightElbow"
    right_hand = "RightWrist"
"""

from __future__ import annotations

import os
import stat
import tomllib
from pathlib import Path

from ergosim.errors import ConfigError
from ergosim.worker.bvh_mapping import ROLES

__all__ = ["read_name_map", "MAX_MAP_BYTES"]

MAX_MAP_BYTES = 1 << 20  # a map has at most a dozen lines


def read_name_map(path: str | os.PathLike[str], where: str = "--map") -> dict[str, str]:
    """role -> joint name from the TOML file at ``path``; ConfigError naming the file and key otherwise."""
    p = Path(path)
    src = str(p)
    try:
        st = p.stat()
        if not stat.S_ISREG(st.st_mode):
            raise ConfigError("not a regular file; expected a joint-name map (.toml)", where=src)
        if st.st_size > MAX_MAP_BYTES:
            raise ConfigError(f"{st.st_size} bytes, more than a map's limit of {MAX_MAP_BYTES}", where=src)
        doc = tomllib.loads(p.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ConfigError(f"no such file {src}", where=where) from None
    except (OSError, UnicodeDecodeError) as err:
        raise ConfigError(f"cannot read the map: {err}", where=src) from None
    except tomllib.TOMLDecodeError as err:
        raise ConfigError(f"invalid TOML: {err}", where=src) from None
    if not doc:
        raise ConfigError(f"the map is empty; give role = \"JointName\" lines, roles: {', '.join(ROLES)}",
                          where=src)
    out = {}
    for key, value in doc.items():
        if key not in ROLES:
            raise ConfigError(f"unknown role {key!r}; roles are {', '.join(ROLES)}", where=f"{src}: {key}")
        if not isinstance(value, str) or not value.strip():
            raise ConfigError(f"expected a BVH joint name (a string), got {value!r}", where=f"{src}: {key}")
        out[key] = value.strip()
    return out
