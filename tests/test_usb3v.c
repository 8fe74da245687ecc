/* USB3 Vision diagnosis (polarcam/usb3v.h): each problem a user can have is named with its fix,
 * and a device without problems is usable; the camera profile table answers by vendor/model
 * prefix and lists the raw formats that carry the mosaic. */
#include <string.h>

#include "check.h"
#include "polarcam/camera_profile.h"
#include "polarcam/usb3v.h"

int main(void)
{
	char note[512];
	CHECK(pc_usb3v_diagnose(PC_USB_SPEED_SUPER, PC_USB_OPEN_OK, 1000, 0x1ab2, 0x0001, 2, 5,
	                        note, sizeof note));
	CHECK_EQ_INT(strlen(note), 0);
	/* permission: the udev rule names the vendor and product ids */
	CHECK(!pc_usb3v_diagnose(PC_USB_SPEED_SUPER, PC_USB_OPEN_ACCESS, 1000, 0x1ab2, 0x0001, 2, 5,
	                         note, sizeof note));
	CHECK(strstr(note, "/dev/bus/usb/002/005") && strstr(note, "idVendor}==\"1ab2\"") &&
	      strstr(note, "idProduct}==\"0001\"") && strstr(note, "udev"));
	/* a USB 2 port */
	CHECK(!pc_usb3v_diagnose(PC_USB_SPEED_HIGH, PC_USB_OPEN_OK, 1000, 1, 2, 1, 1, note,
	                         sizeof note));
	CHECK(strstr(note, "not SuperSpeed") && strstr(note, "480"));
	/* Linux's default usbfs limit (16 MB) */
	CHECK(!pc_usb3v_diagnose(PC_USB_SPEED_SUPER_PLUS, PC_USB_OPEN_OK, 16, 1, 2, 1, 1, note,
	                         sizeof note));
	CHECK(strstr(note, "16 MB") && strstr(note, "usbfs_memory_mb"));
	/* several problems at once, all reported; unknown limit is not a problem */
	CHECK(!pc_usb3v_diagnose(PC_USB_SPEED_FULL, PC_USB_OPEN_BUSY, 16, 1, 2, 1, 1, note,
	                         sizeof note));
	CHECK(strstr(note, "claimed") && strstr(note, "SuperSpeed") && strstr(note, "usbfs"));
	CHECK(pc_usb3v_diagnose(PC_USB_SPEED_UNKNOWN, PC_USB_OPEN_OK, -1, 1, 2, 1, 1, note,
	                        sizeof note));
	/* a short buffer is never overrun */
	char small[8];
	pc_usb3v_diagnose(PC_USB_SPEED_LOW, PC_USB_OPEN_ACCESS, 1, 1, 2, 1, 1, small, sizeof small);
	CHECK(memchr(small, '\0', sizeof small) != NULL);

	const pc_camera_profile *p = pc_camera_profile_find("LUCID Vision Labs", "PHX050S-PC");
	CHECK(p != NULL);
	if (p) {
		CHECK_EQ_INT(p->bits, 12);
		CHECK(pc_camera_profile_has_format(p, "PolarizeMono12p"));
		CHECK(!pc_camera_profile_has_format(p, "PolarizeMono1"));
		CHECK(!pc_camera_profile_has_format(p, "Mono8"));
	}
	p = pc_camera_profile_find("Basler", "acA2440-75umPOL");
	CHECK(p && pc_camera_profile_has_format(p, "Mono12"));
	CHECK(pc_camera_profile_find("Basler", "acA2440-75um") == NULL);
	CHECK(pc_camera_profile_find("Nobody", "X") == NULL);
	for (p = pc_camera_profiles(); p->vendor; p++) {
		pc_mosaic m;
		CHECK_EQ_INT(pc_mosaic_parse(p->mosaic, &m), 0);
	}
	return pc_test_finish("test_usb3v");
}
