!> Verification: the boundary and transfer terms of the energy balance against closed forms
!> of one step of the discrete scheme (cpGIMP, 2 x 2 particles per cell of size dx = 1, no
!> gravity, a stress-free elastic block of mass M filling nb = 4 cells in y).
!>
!> 1. An impact. The block, resting on the floor (its particle domains reach it: gap 0),
!>    moves down at v0 at the start. P2G maps the uniform field exactly: every node moves at
!>    v0. The floor row of nodes carries the weights 3/4 and 1/4 of the two particle rows of
!>    the first cell, one row's mass, M / (2 nb); the floor stops it, so the boundary term is
!>    1/2 M / (2 nb) v0^2 = M v0^2 / 16 after the step, for a fixed floor (held components)
!>    and for a frictional one (the normal constraint of a contact), MUSL and USL, APIC and
!>    PIC (flip_fraction 0). Without the term the balance would lose 6 % of the kinetic
!>    energy in the step. FLIP keeps the particles' velocities beside a held component (its
!>    acceleration is zero): no term, and their kinetic energy stays.
!>    A frictional floor under FLIP (MUSL) is booked by what its normal impulse takes from
!>    the particles: the floor row's change +v0 gives the particle rows of the first cell
!>    3/4 v0 and 1/4 v0, so they keep -v0/4 and -3 v0/4, and their kinetic energy falls by
!>    1/2 (M / 8) v0^2 (2 - 1/16 - 9/16) = 11 M v0^2 / 128: the boundary term, exactly; the
!>    residual is then the elastic energy of the step's strain.
!> 2. A projection loss. Between sliding faces (y) the block moves along x with particle
!>    velocities alternating +v0 (the particle rows at dx/4 in each cell) and -v0 (at 3 dx/4),
!>    PIC (flip_fraction 0). An inner node row gets +v0 with weight 1/4 + 3/4 and -v0 with
!>    3/4 + 1/4: it is at rest; the bottom row takes +v0 3/4, -v0 1/4 of one row's mass,
!>    v0 / 2, the top row -v0 / 2. G2P gives the particles 3/4 and 1/4 of those: 3/8 and 1/8
!>    v0, so the particles keep 2 (1/2) M / (2 nb) ((3/8)^2 + (1/8)^2) v0^2 of 1/2 M v0^2;
!>    no force acts in the first step, so the transfer term is the difference,
!>    M v0^2 (1/2 - 5 / (64 nb)), and the residual is the elastic energy of the step's strain
!>    (no force has acted on the momentum yet).
!> 3. The projection of 2 under a FLIP-PIC blend of fraction a (flip_fraction): no force acts,
!>    so FLIP alone keeps each particle at +-v0, and the blend gives it a v_p + (1 - a) v_PIC
!>    with the PIC velocities of 2: the inner rows a (+-v0), the rows of the bottom and top
!>    cells (a + 3 (1 - a) / 8) v0 and (a - (1 - a) / 8) v0 in size, two rows each. The
!>    transfer term is what the blend took, sum_rows 1/2 (M / (2 nb)) v0^2 (1 - c_row^2) =
!>    M v0^2 / (4 nb) (2 nb - (2 nb - 4) a^2 - 2 (a + 3 (1 - a) / 8)^2 - 2 (a - (1 - a) / 8)^2),
!>    which is 2's at a = 0; the residual is again the elastic energy of the step's strain.
!>    (Not USF: its stress update comes before the momentum, so a force acts in the step.)
program test_boundary_transfer
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step, &
        start_energy_balance, energy_residual
    implicit none

    type(test_suite_type) :: suite
    real(wp), parameter :: v0 = 0.1_wp
        !! speed of the falling blocks [m/s]

    call new_suite(suite, "boundary_transfer")
    call impact('"fixed"', "MUSL", "apic", "fixed floor, MUSL, APIC")
    call impact('"fixed"', "USL", "flip", "fixed floor, USL, PIC")
    call impact('{"type": "frictional", "mu": 0.3}', "MUSL", "apic", "frictional floor, MUSL, APIC")
    call impact('{"type": "frictional", "mu": 0.3}', "USL", "flip", &
        "frictional floor, USL, PIC")
    call flip_keeps()
    call flip_impact()
    call projection("MUSL")
    call projection("USL")
    call blend_projection("MUSL")
    call blend_projection("USL")
    call finish(suite)

contains

    !> The simulation of a block of 4 x 4 cells at the bottom of a domain of 4 x ny cells;
    !> `ok` false (and a failed check) when the case or the simulation cannot be made.
    subroutine new_block(floor, top, ny, scheme, transfer, label, sim, ok)
        character(len=*), intent(in) :: floor, top, ny, scheme, transfer, label
            !! conditions of the faces ymin and ymax, cells along y, scheme, transfer keys,
            !! label of the checks
        type(simulation_type), intent(out) :: sim
            !! the simulation
        logical, intent(out) :: ok
            !! the simulation was made

        type(case_type) :: case
        type(error_type), allocatable :: error

        call read_case_string('{"name": "block", "domain": {"nx": 4, "ny": '//ny//', "dx": 1, '// &
            '"boundaries": {"xmin": "free", "xmax": "free", "ymin": '//floor//', "ymax": '// &
            top//'}}, "particles": {"ppc": 2}, "materials": [{"name": "m", "type": '// &
            '"linear_elastic", "E": 1000, "nu": 0.2, "rho": 10}], "bodies": [{"material": '// &
            '"m", "min": [0, 0], "max": [4, 4]}], "gravity": [0, 0], "solver": {"scheme": "'// &
            scheme//'", "shape_function": "cpgimp", '//transfer//'}, '// &
            '"time": {"tend": 1, "cfl": 0.2}}', case, error, "block")
        if (.not. allocated(error)) call new_simulation(sim, case, error)
        ok = .not. allocated(error)
        call check(suite, ok, label//": case and simulation are valid")
        if (.not. ok) print "(a)", error%message
    end subroutine new_block

    !> Start the energy balance from the particles as set and advance one step.
    subroutine first_step(sim, label, ok)
        type(simulation_type), intent(inout) :: sim
            !! the simulation, velocities set
        character(len=*), intent(in) :: label
            !! label of the checks
        logical, intent(out) :: ok
            !! the step ran

        type(error_type), allocatable :: error

        call start_energy_balance(sim)
        call advance(sim, stable_time_step(sim), error)
        ok = .not. allocated(error)
        call check(suite, ok, label//": step runs")
    end subroutine first_step

    !> The block of new_block on the floor (ymin) moving down at v0, advanced by one step.
    subroutine falling_block(floor, scheme, transfer, label, sim, mass, ok)
        character(len=*), intent(in) :: floor, scheme, transfer, label
            !! condition of the floor, scheme, transfer keys, label of the checks
        type(simulation_type), intent(out) :: sim
            !! the simulation after the step
        real(wp), intent(out) :: mass
            !! mass of the block [kg/m]
        logical, intent(out) :: ok
            !! the simulation was made and the step ran

        integer :: p

        mass = 0.0_wp
        call new_block(floor, '"free"', "8", scheme, transfer, label, sim, ok)
        if (.not. ok) return
        do p = 1, sim%particles%n
            sim%particles%v(:, p) = [0.0_wp, -v0]
        end do
        mass = sum(sim%particles%mass)
        call first_step(sim, label, ok)
    end subroutine falling_block

    !> The block moving down onto the floor: the boundary term after one step.
    subroutine impact(floor, scheme, transfer, label)
        character(len=*), intent(in) :: floor, scheme, transfer, label
            !! condition of the floor (ymin), scheme, transfer, label of the checks

        type(simulation_type) :: sim
        real(wp) :: mass, expected
        logical :: ok

        if (transfer == "flip") then
            call falling_block(floor, scheme, '"transfer": "flip", "flip_fraction": 0', label, &
                sim, mass, ok)
        else
            call falling_block(floor, scheme, '"transfer": "'//transfer//'"', label, sim, mass, ok)
        end if
        if (.not. ok) return
        expected = mass*v0**2/16.0_wp
        call check_close(suite, sim%energy%boundary, expected, 1.0e-12_wp*expected, &
            label//": boundary = 1/2 (M / 8) v0^2")
        print "(a,3(a,es12.5))", label, ": boundary ", sim%energy%boundary, " J/m, expected ", &
            expected, ", residual ", energy_residual(sim%energy)
    end subroutine impact

    !> FLIP: the particles beside a fixed floor keep their velocity (its acceleration is
    !> zero), nothing is booked.
    subroutine flip_keeps()
        type(simulation_type) :: sim
        real(wp) :: mass
        logical :: ok

        call falling_block('"fixed"', "MUSL", '"transfer": "flip"', "FLIP", sim, mass, ok)
        if (.not. ok) return
        call check(suite, sim%energy%boundary == 0.0_wp .and. sim%energy%transfer == 0.0_wp, &
            "FLIP, fixed floor: no boundary or transfer term")
        ! no force acts in the first step (stress-free, no gravity): the velocities stay
        call check(suite, abs(sim%energy%kinetic - sim%energy%initial) < &
            1.0e-12_wp*sim%energy%initial, "FLIP, fixed floor: the particles keep their "// &
            "kinetic energy")
        print "(a,2es12.5)", "FLIP, fixed floor: kinetic / initial - 1, residual / initial ", &
            sim%energy%kinetic/sim%energy%initial - 1.0_wp, &
            energy_residual(sim%energy)/sim%energy%initial
    end subroutine flip_keeps

    !> FLIP, MUSL, frictional floor: the boundary term is the particles' loss of kinetic
    !> energy to the normal impulse.
    subroutine flip_impact()
        character(len=*), parameter :: label = "FLIP, frictional floor, MUSL"
        type(simulation_type) :: sim
        real(wp) :: mass, expected
        logical :: ok

        call falling_block('{"type": "frictional", "mu": 0.3}', "MUSL", '"transfer": "flip"', &
            label, sim, mass, ok)
        if (.not. ok) return
        expected = 11.0_wp*mass*v0**2/128.0_wp
        call check_close(suite, sim%energy%boundary, expected, 1.0e-12_wp*expected, &
            label//": boundary = 11 M v0^2 / 128")
        call check_close(suite, sim%energy%initial - sim%energy%kinetic, expected, &
            1.0e-12_wp*expected, label//": the particles lost 11 M v0^2 / 128")
        call check(suite, abs(energy_residual(sim%energy) - sim%energy%elastic) < &
            1.0e-12_wp*expected, label//": residual = elastic energy of the step")
        print "(a,3(a,es12.5))", label, ": boundary ", sim%energy%boundary, " J/m, expected ", &
            expected, ", residual ", energy_residual(sim%energy)
    end subroutine flip_impact

    !> The block between sliding faces (it fills the domain in y: 4 cells) moving along x
    !> with particle velocities alternating +v0 (rows at dx/4 in each cell) and -v0 (at
    !> 3 dx/4), advanced by one step.
    subroutine alternating_block(scheme, transfer, label, sim, mass, ok)
        character(len=*), intent(in) :: scheme, transfer, label
            !! scheme, transfer keys, label of the checks
        type(simulation_type), intent(out) :: sim
            !! the simulation after the step
        real(wp), intent(out) :: mass
            !! mass of the block [kg/m]
        logical, intent(out) :: ok
            !! the simulation was made and the step ran

        real(wp) :: offset
        integer :: p

        mass = 0.0_wp
        call new_block('"sliding"', '"sliding"', "4", scheme, transfer, label, sim, ok)
        if (.not. ok) return
        do p = 1, sim%particles%n
            offset = sim%particles%x(2, p) - real(floor(sim%particles%x(2, p)), wp)
            sim%particles%v(:, p) = [merge(v0, -v0, offset < 0.5_wp), 0.0_wp]
        end do
        mass = sum(sim%particles%mass)
        call first_step(sim, label, ok)
    end subroutine alternating_block

    !> PIC of alternating particle velocities: the transfer term after one step.
    subroutine projection(scheme)
        character(len=*), intent(in) :: scheme
            !! scheme

        real(wp), parameter :: nb = 4.0_wp
        type(simulation_type) :: sim
        real(wp) :: mass, expected
        logical :: ok
        character(len=:), allocatable :: label

        label = scheme//", PIC, alternating velocities"
        call alternating_block(scheme, '"transfer": "flip", "flip_fraction": 0', label, sim, &
            mass, ok)
        if (.not. ok) return
        expected = mass*v0**2*(0.5_wp - 5.0_wp/(64.0_wp*nb))
        call check_close(suite, sim%energy%transfer, expected, 1.0e-12_wp*expected, &
            label//": transfer = M v0^2 (1/2 - 5 / (64 nb))")
        ! no force acted on the momentum in the step: what the balance gained is the elastic
        ! energy of the step's strain (the explicit scheme's half-step lag), nothing else
        call check(suite, abs(energy_residual(sim%energy) - sim%energy%elastic) < &
            1.0e-12_wp*expected, label//": residual = elastic energy of the step")
        call check(suite, abs(sim%energy%boundary) < 1.0e-12_wp*expected, &
            label//": nothing stopped by the sliding faces")
        print "(a,3(a,es12.5))", label, ": transfer ", sim%energy%transfer, " J/m, expected ", &
            expected, ", residual ", energy_residual(sim%energy)
    end subroutine projection

    !> A FLIP-PIC blend of alternating particle velocities: the transfer term after one step
    !> is the kinetic energy the blend's PIC part took.
    subroutine blend_projection(scheme)
        character(len=*), intent(in) :: scheme
            !! scheme

        real(wp), parameter :: nb = 4.0_wp, a = 0.9_wp
        type(simulation_type) :: sim
        real(wp) :: mass, expected
        logical :: ok
        character(len=:), allocatable :: label

        label = scheme//", FLIP-PIC blend 0.9, alternating velocities"
        call alternating_block(scheme, '"transfer": "flip", "flip_fraction": 0.9', label, &
            sim, mass, ok)
        if (.not. ok) return
        expected = mass*v0**2/(4.0_wp*nb)*(2.0_wp*nb - (2.0_wp*nb - 4.0_wp)*a**2 &
            - 2.0_wp*(a + 3.0_wp*(1.0_wp - a)/8.0_wp)**2 - 2.0_wp*(a - (1.0_wp - a)/8.0_wp)**2)
        call check_close(suite, sim%energy%transfer, expected, 1.0e-12_wp*expected, &
            label//": transfer = the kinetic energy the blend took")
        call check(suite, abs(energy_residual(sim%energy) - sim%energy%elastic) < &
            1.0e-12_wp*expected, label//": residual = elastic energy of the step")
        print "(a,3(a,es12.5))", label, ": transfer ", sim%energy%transfer, " J/m, expected ", &
            expected, ", residual ", energy_residual(sim%energy)
    end subroutine blend_projection

end program test_boundary_transfer
