"""What the names of links and joints say: the words they are made of and the part of a robot
they name (wheel, gripper, head, arm, leg, tool, sensor), as :mod:`.chains` reads them.

Names are split into words at non-letters and camelCase humps; a word that begins or ends with
a wheel word, or ends with ``hand``, ``gripper`` or ``finger``, counts too (``wheelfl``,
``qbhand``).
"""

from __future__ import annotations

import re
from collections.abc import Collection
from functools import lru_cache
from typing import Literal

__all__ = [
    "ARM",
    "HEAD",
    "LEG",
    "SENSOR",
    "TOOL_RANKS",
    "TOOL_WORDS",
    "JointRole",
    "name_role",
    "name_words",
    "says_finger",
    "says_gripper",
    "says_hand",
    "says_jaw",
    "says_sensor",
    "turns_hand",
]

#: Why a joint is left out of a default c-space.
JointRole = Literal["wheel", "gripper", "head"]

WHEEL = frozenset({"wheel", "wheels", "caster", "castor", "tire", "tyre"})
GRIPPER = frozenset(
    {
        "gripper",
        "grip",
        "finger",
        "fingers",
        "fngr",
        "hand",
        "jaw",
        "claw",
        "thumb",
        "knuckle",
        "palm",
        "pinky",
        "pinkie",
    }
)
HEAD = frozenset(
    {"head", "neck", "camera", "cam", "eye", "eyes", "laser", "lidar", "xtion", "kinect"}
)
PAN_TILT = frozenset({"pan", "tilt"})
HAND = frozenset({"hand", "palm"})
#: Finger words beside the gripper words (Robonaut 2's 'r2/left_arm/hand/index/yaw').
FINGER = frozenset({"index", "middle", "ring", "little", "mcp", "pip", "dip", "distal", "tip"})
#: Words of a finger's joint: a finger, a thumb or one of their parts.
FINGERS = FINGER | {"finger", "fingers", "fngr", "thumb", "knuckle", "pinky", "pinkie"}
#: Words of a link that only a gripper's finger or jaw is (Spot's 'arm_link_fngr'): a joint
#: into such a link moves a jaw, however the joint is named.
JAW_LINK = frozenset({"finger", "fingers", "fngr", "jaw", "claw", "thumb", "pinky", "pinkie"})
ROTATION = frozenset({"roll", "pitch", "yaw"})
ARM = frozenset({"shoulder", "elbow", "wrist", "arm", "forearm", "upperarm"})
#: Words of a leg's joints and links: a humanoid's leg is as long as its arm, but not planned.
LEG = frozenset(
    {"leg", "legs", "hip", "knee", "ankle", "foot", "feet", "toe", "thigh", "shin", "calf"}
)

#: Tool-frame name preferences, best first: (rank, words or exact name).
TOOL_RANKS: tuple[tuple[str, frozenset[str]], ...] = (
    ("a TCP", frozenset({"tcp"})),
    ("a tool", frozenset({"tool", "tool0"})),
    ("an end-effector", frozenset({"ee", "eef", "effector", "endeffector", "endpoint"})),
    ("a flange", frozenset({"flange"})),
    ("a grasp", frozenset({"grasp", "grasping"})),
)
#: Words of a frame a tool is mounted at (a grasp frame may sit between fingers).
TOOL_WORDS = frozenset().union(*(names for rank, names in TOOL_RANKS if rank != "a grasp"))
SENSOR = HEAD | {
    *("optical", "depth", "rgb", "imu", "sensor", "accelerometer", "accel", "gyrometer", "gyro"),
    *("range", "sonar", "infrared", "touch", "tactile", "skin", "bumper", "button", "fsr"),
    *("realsense", "zed", "orbbec", "astra", "femto"),
}
#: Depth camera models whose names hold digits, which :func:`name_words` drops (``d405_link``
#: is the words d, link): Intel RealSense D4xx, L515 and SR30x.
_CAMERA_MODEL = re.compile(r"(?<![A-Za-z0-9])(?:[dD]4\d\d[iI]?|[lL]515|[sS][rR]30\d)(?![0-9])")


@lru_cache(maxsize=65536)
def name_words(name: str) -> tuple[str, ...]:
    """Lower-case words of a link or joint name: split at non-letters and camelCase humps
    (an upper-case run before a capitalized word is a word: NAO's ``LHipPitch`` is l, hip,
    pitch)."""
    spaced = re.sub(r"([a-z])([A-Z])", r"\1 \2", name)
    spaced = re.sub(r"([A-Z]+)([A-Z][a-z])", r"\1 \2", spaced)
    return tuple(w.lower() for w in re.split(r"[^A-Za-z]+", spaced) if w)


#: Words that name a wheel or a hand inside a compound written as one word (``wheelfl``,
#: ``qbhand``, ``lefthand``): a word beginning or ending with a wheel word, ending with these.
WHEEL_AFFIXES = ("wheel", "caster", "castor")
GRIPPER_ENDINGS = ("hand", "gripper", "finger", "fingers")


def name_role(name: str) -> JointRole | None:
    """Why a joint or link name is no arm's: a wheel, a gripper or a head (None: it says
    none of these)."""
    words = set(name_words(name))
    if words & WHEEL or any(
        w.startswith(WHEEL_AFFIXES) or w.endswith(WHEEL_AFFIXES) for w in words
    ):
        return "wheel"
    if words & GRIPPER or any(w.endswith(GRIPPER_ENDINGS) for w in words):
        return "gripper"
    if words & HEAD or (words & PAN_TILT and not words & ARM):
        return "head"
    return None


def says_sensor(name: str) -> bool:
    """Whether a link or joint name speaks of a sensor or a camera (``camera_color_optical_frame``,
    ``d405_link``): a frame no tool is mounted at."""
    return bool(set(name_words(name)) & SENSOR) or _CAMERA_MODEL.search(name) is not None


def says_gripper(name: str) -> bool:
    """Whether a link name speaks of a gripper or a hand (``gripper_frame_link``)."""
    words = set(name_words(name))
    return bool(words & GRIPPER) or any(w.endswith(GRIPPER_ENDINGS) for w in words)


def says_hand(words: Collection[str]) -> bool:
    """Whether a name speaks of a whole hand (``hand``, ``palm``, ``lefthand``) and of no
    finger, jaw or gripper."""
    words = set(words)
    hand = words & HAND or any(w.endswith("hand") for w in words)
    return bool(hand) and not words & (GRIPPER | FINGER) - HAND


def says_jaw(name: str) -> bool:
    """Whether a link name says the link is a finger or a jaw (``arm_link_fngr``)."""
    return bool(set(name_words(name)) & JAW_LINK)


def says_finger(words: Collection[str]) -> bool:
    """Whether a joint's name speaks of a finger or a thumb (``L_index_proximal_joint``)."""
    return bool(set(words) & FINGERS)


def turns_hand(words: Collection[str]) -> bool:
    """Whether a joint's name says it turns a whole hand about an axis: a wrist joint."""
    return says_hand(words) and bool(set(words) & ROTATION)
