"""Camera driver on generated video files and missing devices; Image/LaserScan conversions."""

import time

import cv2
import numpy as np
import pytest

from joshua_runtime.convert import image as image_convert
from joshua_runtime.convert import laser_scan as scan_convert
from joshua_runtime.drivers.camera import CameraDriver, frame_to_packet
from joshua_runtime.errors import DeviceError, SettingsError

WIDTH, HEIGHT, FRAMES = 160, 120, 12
CODEC_TOLERANCE = 4  # max mean absolute error of a lossy codec on flat colours


def frame_colour(i: int) -> tuple[int, int, int]:
    return (i * 20 % 256, 255 - i * 15, 60 + i * 10)


def write_video(path, fourcc: str) -> None:
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*fourcc), 30.0, (WIDTH, HEIGHT))
    assert writer.isOpened()
    for i in range(FRAMES):
        writer.write(np.full((HEIGHT, WIDTH, 3), frame_colour(i), np.uint8))
    writer.release()


@pytest.mark.parametrize(("name", "fourcc"), [("clip.avi", "MJPG"), ("clip.mp4", "mp4v")])
def test_video_file_frames_come_out_in_order_and_loop(tmp_path, name, fourcc):
    path = tmp_path / name
    write_video(path, fourcc)
    before = time.time_ns()
    with CameraDriver(video_source=str(path), width=WIDTH, height=HEIGHT, frame_id="wrist") as camera:
        packets = [camera.read() for _ in range(FRAMES + 2)]
    for i, packet in enumerate(packets):
        image = packet.image
        assert (image.width, image.height, image.encoding, image.step) == (WIDTH, HEIGHT, "bgr8", WIDTH * 3)
        assert len(image.data) == WIDTH * HEIGHT * 3
        assert packet.frame_id == "wrist"
        assert before <= packet.timestamp.ToNanoseconds() <= time.time_ns()
        pixels = image_convert.packet_pixels(packet).astype(int)
        error = np.abs(pixels - np.array(frame_colour(i % FRAMES))).mean()
        assert error < CODEC_TOLERANCE, (i, error)


def test_frames_are_resized_to_the_requested_size(tmp_path):
    write_video(tmp_path / "clip.avi", "MJPG")
    with CameraDriver(video_source=str(tmp_path / "clip.avi"), width=64, height=48) as camera:
        assert camera.read_frame().shape == (48, 64, 3)


def test_missing_camera_index_is_a_clear_device_error():
    with pytest.raises(DeviceError, match=r"^cannot open camera 57 \(/dev/video57\): no such device$") as info:
        CameraDriver(camera_index=57).open()
    assert info.value.exit_code == 3


def test_missing_video_file_is_a_clear_device_error(tmp_path):
    missing = tmp_path / "nothing.mp4"
    with pytest.raises(DeviceError, match=rf"^cannot open video source {missing}: no such file$"):
        CameraDriver(video_source=str(missing)).open()


def _packet(encoding="bgr8"):
    rng = np.random.default_rng(5)
    frame = rng.integers(0, 256, (HEIGHT, WIDTH, 3), np.uint8)
    packet = frame_to_packet(frame, "cam", 1_700_000_000_123_456_789)
    packet.image.encoding = encoding
    return packet, frame


def test_image_round_trip_is_exact():
    packet, _ = _packet()
    message = image_convert.packet_to_message(packet, "sensor_msgs/msg/Image")
    assert (message.header.stamp.sec, message.header.stamp.nanosec) == (1_700_000_000, 123_456_789)
    assert (message.header.frame_id, message.width, message.height, message.step) == ("cam", WIDTH, HEIGHT, WIDTH * 3)
    assert message.encoding == "bgr8" and message.is_bigendian == 0
    assert image_convert.message_to_packet(message) == packet


def test_png_compressed_round_trip_is_exact_and_jpeg_is_close():
    packet, frame = _packet()
    png = image_convert.packet_to_compressed_image(packet, "png")
    assert png.format == "png"
    back = image_convert.compressed_image_to_packet(png)
    assert back == packet
    flat = frame_to_packet(np.full((HEIGHT, WIDTH, 3), (10, 200, 90), np.uint8), "cam", 5)
    jpeg = image_convert.packet_to_message(flat, "sensor_msgs/msg/CompressedImage")
    assert jpeg.format == "jpeg" and bytes(jpeg.data[:2]) == b"\xff\xd8"
    decoded = image_convert.packet_pixels(image_convert.message_to_packet(jpeg)).astype(int)
    assert np.abs(decoded - np.array((10, 200, 90))).max() <= 2


def test_unsupported_camera_message_type_is_a_settings_error():
    packet, _ = _packet()
    with pytest.raises(SettingsError, match="cannot publish 'sensor_msgs/msg/LaserScan'"):
        image_convert.packet_to_message(packet, "sensor_msgs/msg/LaserScan")


def test_laser_scan_round_trip():
    from joshua_core.schema import PerceptionPacket

    packet = PerceptionPacket(frame_id="laser")
    packet.timestamp.FromNanoseconds(42_000_000_007)
    sensor = packet.sensor
    sensor.kind = "laser_scan"
    sensor.ranges.extend([0.5, 0.0, 3.25])
    sensor.intensities.extend([100.0, 0.0, 7.0])
    sensor.angle_min, sensor.angle_max, sensor.angle_increment = 0.0, 2.0, 1.0
    sensor.range_min, sensor.range_max = 0.12, 3.5
    sensor.time_increment, sensor.scan_time = 0.25, 0.75
    message = scan_convert.packet_to_laser_scan(packet)
    assert (message.header.stamp.sec, message.header.stamp.nanosec, message.header.frame_id) == (42, 7, "laser")
    assert list(message.ranges) == [0.5, 0.0, 3.25]
    assert message.scan_time == 0.75
    assert scan_convert.laser_scan_to_packet(message) == packet
