	# The hullpose system user, in the groups that own cameras (video) and GPIO chips (gpio).
	if command -v systemd-sysusers >/dev/null 2>&1; then
		systemd-sysusers /usr/lib/sysusers.d/hullpose.conf
	else
		getent group hullpose >/dev/null || addgroup --quiet --system hullpose
		getent passwd hullpose >/dev/null || adduser --quiet --system --ingroup hullpose --home /nonexistent --no-create-home hullpose
		getent group gpio >/dev/null || addgroup --quiet --system gpio
		for g in video gpio; do adduser --quiet hullpose "$g" || true; done
	fi
	# LCM's receive buffers (net.core.rmem_max) and the GPIO chips' group, now rather than at the next boot.
	if [ -d /run/systemd/system ]; then
		/usr/lib/systemd/systemd-sysctl /usr/lib/sysctl.d/60-hullpose.conf || true
		udevadm control --reload-rules || true
		udevadm trigger --subsystem-match=gpio || true
	fi
