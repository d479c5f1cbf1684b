!> The `time` key of a case: end time and either a fixed step or a CFL factor.
module mpm_case_time
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: fmt_real, fmt_below
    use mpm_case_cursor, only: cursor_type
    use mpm_case_materials, only: material_spec_type
    use mpm_case_bodies, only: body_spec_type
    use mpm_case_stability, only: start_time_step
    implicit none
    private
    public :: time_section_type, read_time, time_keys

    character(len=*), parameter :: time_keys(*) = [character(len=14) :: "tend", "dt", "cfl", &
        "allow_unstable"]
        !! keys of `time`
    real(wp), parameter :: max_steps = 1.0e9_wp
        !! largest number of time steps a case may need

    !> `time`: how long the run lasts and how its step is chosen.
    type :: time_section_type
        real(wp) :: dt = 0.0_wp
            !! fixed time step [s]; 0 when the CFL condition sets it
        real(wp) :: cfl = 0.5_wp
            !! CFL factor C in dt = C dx / max_p (c_p + |v_p|) [-]
        logical :: allow_unstable = .false.
            !! accept dt above the critical step or cfl > 1 (stability tests; the blow-up guard
            !! then stops the run)
        real(wp) :: tend = 0.0_wp
            !! end time [s]
    end type time_section_type

contains

    !> `time`: end time and either a fixed step or a CFL factor, checked against the critical
    !> time step of the materials and bodies.
    subroutine read_time(root, dim, dx, materials, bodies, time, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        integer, intent(in) :: dim
            !! number of space dimensions
        real(wp), intent(in) :: dx
            !! cell size [m]
        type(material_spec_type), intent(in) :: materials(:)
            !! materials of the case
        type(body_spec_type), allocatable, intent(in) :: bodies(:)
            !! bodies of the case
        type(time_section_type), intent(inout) :: time
            !! the time section
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: cur
        character(len=:), allocatable :: rule
        logical :: viscous
        real(wp) :: critical, step
        integer :: m

        call root%get_section("time", time_keys, cur, error, required=.true.)
        if (allocated(error)) return
        call cur%get_real("tend", time%tend, error, required=.true., above=0.0_wp, unit="s")
        if (allocated(error)) return
        call cur%get_bool("allow_unstable", time%allow_unstable, error)
        if (allocated(error)) return
        call start_time_step(dim, dx, materials, bodies, critical, viscous)
        rule = "dx / max(c_p + |v|)"
        if (viscous) rule = "the viscous limit rho dx^2 / (2 dim viscosity) of a newtonian " &
            //"material, or the diffusion limit dx^2 / (2 dim D) of the pore pressure of a " &
            //"saturated soil (D = k K_w / (gamma_w n))"
        if (cur%has("dt")) then
            if (cur%has("cfl")) then
                call cur%fail(error, "time.dt and time.cfl are alternatives, give only " &
                    //"one: dt for a fixed time step [s], cfl for a step set by the CFL " &
                    //"condition")
                return
            end if
            call cur%get_real("dt", time%dt, error, above=0.0_wp, unit="s")
            if (allocated(error)) return
            do m = 1, size(materials)
                if (.not. allocated(materials(m)%law) .or. time%allow_unstable) cycle
                if (.not. materials(m)%law%speed_varies()) cycle
                call cur%fail(error, "time.dt: material '"//materials(m)%name//"' stiffens " &
                    //"as it is loaded (its wave speed follows the stress), so no fixed step " &
                    //"is known to stay stable; use time.cfl, which follows it " &
                    //"(time.allow_unstable = true forces dt)")
                return
            end do
            if (time%dt > critical .and. .not. time%allow_unstable) then
                call cur%fail(error, "time.dt = "//fmt_real(time%dt)//" s is above the " &
                    //"critical time step "//fmt_below(critical, time%dt)//" s of this case " &
                    //"("//rule//"); use a smaller dt or set time.cfl instead "// &
                    "(time.allow_unstable = true forces it, for stability tests)")
                return
            end if
            step = time%dt
        else
            if (time%allow_unstable) then
                call cur%get_real("cfl", time%cfl, error, above=0.0_wp)
            else
                call cur%get_real("cfl", time%cfl, error, above=0.0_wp, at_most=1.0_wp)
            end if
            if (allocated(error)) return
            step = time%cfl*critical
        end if
        if (time%tend/max_steps > step) then
            call cur%fail(error, "time.tend = "//fmt_real(time%tend)//" s needs more " &
                //"than "//fmt_real(max_steps)//" steps of "//fmt_real(step, 6)//" s; " &
                //"shorten time.tend or allow a larger time step")
        end if
    end subroutine read_time

end module mpm_case_time
