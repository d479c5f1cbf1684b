!> Stability limits of the explicit time step of a case: the P-wave speed of each material,
!> the viscous limit of a fluid, and the critical step of the case at t = 0.
!>
!> The one place these are computed: the case reader checks `time` with them and the solver
!> sets its step from the same functions.
module mpm_case_stability
    use mpm_kinds, only: wp
    use mpm_case_materials, only: material_spec_type
    use mpm_case_bodies, only: body_spec_type
    implicit none
    private
    public :: p_wave_speed, viscous_time_step, critical_time_step, start_time_step, &
        water_wave_term, mobility, standard_gravity

    real(wp), parameter :: standard_gravity = 9.80665_wp
        !! g_n [m/s2]: the unit weight of water in the hydraulic conductivity, gamma_w =
        !! rho_w g_n, whatever the gravity of the case

contains

    !> P-wave speed of a material [m/s], from its law: sqrt((K + 4G/3)/rho) for a solid,
    !> sqrt(K/rho) for a fluid; 0 for a material without a law (made in code). A soil
    !> saturated with pore water: the undrained speed, sqrt(c^2 + K_w/(n rho)).
    pure real(wp) function p_wave_speed(mat)
        type(material_spec_type), intent(in) :: mat
            !! material

        p_wave_speed = 0.0_wp
        if (allocated(mat%law)) p_wave_speed = mat%law%wave_speed()
        if (mat%porosity > 0.0_wp) p_wave_speed = sqrt(p_wave_speed**2 + water_wave_term(mat))
    end function p_wave_speed

    !> K_w / (n rho) of a saturated soil, 0 of a dry material [m2/s2]: what its pore water
    !> adds to the square of its P-wave speed (undrained).
    pure real(wp) function water_wave_term(mat)
        type(material_spec_type), intent(in) :: mat
            !! material

        water_wave_term = 0.0_wp
        if (mat%porosity > 0.0_wp .and. mat%density > 0.0_wp) water_wave_term = &
            mat%water_bulk_modulus/(mat%porosity*mat%density)
    end function water_wave_term

    !> k / gamma_w of a saturated soil [m2/(Pa s)]: Darcy's flux per pressure gradient, from
    !> its hydraulic conductivity k and gamma_w = rho_w g_n; 0 of a dry material.
    pure real(wp) function mobility(mat)
        type(material_spec_type), intent(in) :: mat
            !! material

        mobility = 0.0_wp
        if (mat%porosity > 0.0_wp) mobility = mat%permeability &
            /(mat%water_density*standard_gravity)
    end function mobility

    !> Time-step limit of a material besides the CFL condition [s], from its law: the
    !> viscous limit rho dx^2 / (2 dim mu) of a fluid, huge for the others. A saturated soil
    !> also has the diffusion limit of its pore pressure, dx^2 / (2 dim D) with D = (k /
    !> gamma_w) K_w / n (the explicit update of the pressure, with the volume of the skeleton
    !> held).
    pure real(wp) function viscous_time_step(mat, dx, dim)
        type(material_spec_type), intent(in) :: mat
            !! material
        real(wp), intent(in) :: dx
            !! cell size [m]
        integer, intent(in) :: dim
            !! space dimensions

        real(wp) :: diffusivity

        viscous_time_step = huge(1.0_wp)
        if (allocated(mat%law)) viscous_time_step = mat%law%time_step_limit(dx, dim)
        diffusivity = 0.0_wp
        if (mat%porosity > 0.0_wp) diffusivity = mobility(mat)*mat%water_bulk_modulus &
            /mat%porosity
        if (diffusivity > 0.0_wp) viscous_time_step = min(viscous_time_step, &
            dx**2/(2.0_wp*dim*diffusivity))
    end function viscous_time_step

    !> Critical time step at t = 0 [s]: dx / max over bodies (c_p + |v0|), and the viscous
    !> limit of the materials in use.
    pure real(wp) function critical_time_step(dim, dx, materials, bodies)
        integer, intent(in) :: dim
            !! space dimensions
        real(wp), intent(in) :: dx
            !! cell size [m]
        type(material_spec_type), intent(in) :: materials(:)
            !! materials of the case
        type(body_spec_type), intent(in) :: bodies(:)
            !! bodies of the case

        integer :: b, m
        real(wp) :: speed, viscous

        speed = 0.0_wp
        viscous = huge(1.0_wp)
        do b = 1, size(bodies)
            associate (mat => materials(bodies(b)%material))
                speed = max(speed, p_wave_speed(mat) + norm2(bodies(b)%velocity(1:dim)))
                viscous = min(viscous, viscous_time_step(mat, dx, dim))
            end associate
            ! a particle list: the materials of its particles too
            if (allocated(bodies(b)%list)) then
                do m = 1, size(materials)
                    if (.not. any(bodies(b)%list%material == m)) cycle
                    speed = max(speed, p_wave_speed(materials(m)) + norm2(bodies(b)%velocity(1:dim)))
                    viscous = min(viscous, viscous_time_step(materials(m), dx, dim))
                end do
            end if
        end do
        if (speed > 0.0_wp) then
            critical_time_step = min(dx/speed, viscous)
        else
            critical_time_step = viscous
        end if
    end function critical_time_step

    !> Critical time step at t = 0: over the bodies, or over the materials when the particles
    !> come from a state file (no bodies, velocities unknown here) [s]. Either way the viscous
    !> limit of the newtonian materials in use applies too.
    pure subroutine start_time_step(dim, dx, materials, bodies, dt, viscous)
        integer, intent(in) :: dim
            !! space dimensions
        real(wp), intent(in) :: dx
            !! cell size [m]
        type(material_spec_type), intent(in) :: materials(:)
            !! materials of the case
        type(body_spec_type), allocatable, intent(in) :: bodies(:)
            !! bodies of the case (unallocated or empty: the materials decide)
        real(wp), intent(out) :: dt
            !! critical time step [s]
        logical, intent(out) :: viscous
            !! whether the viscous limit sets the step

        real(wp) :: speed, limit
        integer :: m, b

        limit = huge(1.0_wp)
        if (allocated(bodies)) then
            if (size(bodies) > 0) then
                dt = critical_time_step(dim, dx, materials, bodies)
                do b = 1, size(bodies)
                    limit = min(limit, viscous_time_step(materials(bodies(b)%material), dx, dim))
                    if (.not. allocated(bodies(b)%list)) cycle
                    do m = 1, size(materials)
                        if (any(bodies(b)%list%material == m)) limit = min(limit, &
                            viscous_time_step(materials(m), dx, dim))
                    end do
                end do
                viscous = limit < huge(1.0_wp) .and. dt >= limit
                return
            end if
        end if
        speed = 0.0_wp
        do m = 1, size(materials)
            speed = max(speed, p_wave_speed(materials(m)))
            limit = min(limit, viscous_time_step(materials(m), dx, dim))
        end do
        dt = limit
        if (speed > 0.0_wp) dt = min(dx/speed, limit)
        viscous = limit < huge(1.0_wp) .and. dt >= limit
    end subroutine start_time_step

end module mpm_case_stability
