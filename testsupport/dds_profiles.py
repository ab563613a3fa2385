"""Fast DDS participant profiles for processes on several hosts: the project's profile plus a Discovery Server.

`participant_profile()` writes the XML that docs/multihost-dds.md documents, in the layout of
templates/fastdds_profile.xml.j2 (same discovery timing, same 16 MiB shared-memory segment for the
processes that carry images) with, when a server is named, the Discovery Server client settings. The
multi-host tests load these files (FASTRTPS_DEFAULT_PROFILES_FILE) to establish what works.
"""

from dataclasses import dataclass
from pathlib import Path

# GUID prefix of the server started with `fast-discovery-server -i ID`: this one with byte 2 set to ID.
SERVER_PREFIX_BYTES = [0x44, 0x53, 0x00, 0x5F, 0x45, 0x50, 0x52, 0x4F, 0x53, 0x49, 0x4D, 0x41]
IMAGE_SEGMENT_BYTES = 16 * 1024 * 1024  # the project's images profile (joshua_codegen/emitters/fastdds.py)
ROLES = ("CLIENT", "SUPER_CLIENT")


def server_prefix(server_id: int) -> str:
    """The GUID prefix of `fast-discovery-server -i server_id`, as the XML writes it (dotted hex bytes)."""
    prefix = list(SERVER_PREFIX_BYTES)
    prefix[2] = server_id
    return ".".join(f"{byte:02x}" for byte in prefix)


@dataclass(frozen=True)
class Timing:
    """Discovery timing in milliseconds (the project's: 10 x 100 ms, then every 1 s, lease 10 s)."""

    initial_count: int = 10
    initial_period_ms: int = 100
    announcement_ms: int = 1000
    lease_ms: int = 10_000
    client_announcement_ms: int = 250  # how often a client pings a server it has not matched yet (Fast DDS: 450)


def duration(milliseconds: int) -> str:
    return f"<sec>{milliseconds // 1000}</sec><nanosec>{(milliseconds % 1000) * 1_000_000}</nanosec>"


def participant_profile(
    server: tuple[str, int] | None = None,
    role: str = "CLIENT",
    images: bool = False,
    timing: Timing = Timing(),
    server_id: int = 0,
) -> str:
    """The XML text of the default participant profile; `server` is the Discovery Server's (address, port)."""
    if role not in ROLES:
        raise ValueError(f"role must be one of {ROLES}")
    transports = ""
    user_transports = ""
    if images:
        transports = f"""
    <transport_descriptors>
      <transport_descriptor>
        <transport_id>joshua_shm</transport_id>
        <type>SHM</type>
        <segment_size>{IMAGE_SEGMENT_BYTES}</segment_size>
      </transport_descriptor>
      <transport_descriptor>
        <transport_id>joshua_udp</transport_id>
        <type>UDPv4</type>
      </transport_descriptor>
    </transport_descriptors>"""
        user_transports = """
        <userTransports>
          <transport_id>joshua_shm</transport_id>
          <transport_id>joshua_udp</transport_id>
        </userTransports>
        <useBuiltinTransports>false</useBuiltinTransports>"""
    client = ""
    if server is not None:
        address, port = server
        client = f"""
            <discoveryProtocol>{role}</discoveryProtocol>
            <discoveryServersList>
              <RemoteServer prefix="{server_prefix(server_id)}">
                <metatrafficUnicastLocatorList>
                  <locator>
                    <udpv4>
                      <address>{address}</address>
                      <port>{port}</port>
                    </udpv4>
                  </locator>
                </metatrafficUnicastLocatorList>
              </RemoteServer>
            </discoveryServersList>
            <clientAnnouncementPeriod>{duration(timing.client_announcement_ms)}</clientAnnouncementPeriod>"""
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns="http://www.eprosima.com">
  <profiles>{transports}
    <participant profile_name="joshua_participant" is_default_profile="true">
      <rtps>
        <builtin>
          <discovery_config>{client}
            <leaseDuration>{duration(timing.lease_ms)}</leaseDuration>
            <leaseAnnouncement>{duration(timing.announcement_ms)}</leaseAnnouncement>
            <initialAnnouncements>
              <count>{timing.initial_count}</count>
              <period>{duration(timing.initial_period_ms)}</period>
            </initialAnnouncements>
          </discovery_config>
        </builtin>{user_transports}
      </rtps>
    </participant>
  </profiles>
</dds>
"""


@dataclass(frozen=True)
class ServerTiming:
    """The server's own lease (clients drop a server silent this long) and how often it announces itself."""

    lease_ms: int = 2000
    announcement_ms: int = 500


def server_profile(timing: ServerTiming = ServerTiming()) -> str:
    """The XML text of the Discovery Server's profile (`fast-discovery-server -x`; -i, -l and -p on its command line).

    A short lease makes clients drop a crashed server soon, and a server started again after that lease
    is matched afresh (see docs/multihost-dds.md, "the server restarted").
    """
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns="http://www.eprosima.com">
  <profiles>
    <participant profile_name="joshua_discovery_server" is_default_profile="true">
      <rtps>
        <builtin>
          <discovery_config>
            <discoveryProtocol>SERVER</discoveryProtocol>
            <leaseDuration>{duration(timing.lease_ms)}</leaseDuration>
            <leaseAnnouncement>{duration(timing.announcement_ms)}</leaseAnnouncement>
          </discovery_config>
        </builtin>
      </rtps>
    </participant>
  </profiles>
</dds>
"""


def write_profile(path: Path, **profile_args) -> Path:
    path.write_text(participant_profile(**profile_args))
    return path
