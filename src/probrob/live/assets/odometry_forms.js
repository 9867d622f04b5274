// Tables 5.5 and 5.6 in both noise forms (odometry.js with noise_forms.js): odometry_noise_forms_live.
kernels.odometry_forms = noiseForms(kernels.odometry, 4);
