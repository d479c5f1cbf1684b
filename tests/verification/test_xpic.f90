!> Verification: the XPIC(m) particle update (solver.transfer = "xpic") against its closed
!> form, one step from an arbitrary velocity field with no force.
!>
!> An elastic block of 4 x 2 cells (linear shape functions, 2 x 2 particles per cell, no
!> gravity, no stress: the first step has no nodal acceleration, so MUSL's G2P gives
!> v_p = [I - (I - A)^m] v0 exactly) with a velocity field that mixes a smooth part and the
!> checkerboard the grid cannot see, v0 = (0.1 + 0.02 y/dx + 0.3 (-1)^(i+j), -0.05 + 0.2
!> (-1)^i), i, j the particle's column and row. A = S M^-1 S^T M_p is built here from the
!> linear weights, independently of the code. Checked for m = 1, 2, 3, 6:
!>
!> - the velocities after one step equal [I - (I - A)^m] v0 within 1e-12 of |v0|;
!> - m = 1 gives what PIC gives (transfer "flip" with flip_fraction 0), to round-off;
!> - the kinetic energy removed is booked as transfer loss (energy%transfer), exactly the
!>   kinetic energy of the FLIP velocities (v0, no force) less that of the new ones;
!> - a uniform velocity is kept exactly by every order (A reproduces constants);
!> - with gravity (g = -10 m/s2) on the block resting on a sliding floor (v_y held at the
!>   bottom node row), the velocities equal sum_i N_ip (xpic_i + dt a_i), xpic = sum_k
!>   (-1)^(k+1) C(m, k) u_k, u_1 = v_g and u_k = H A_g u_(k-1), H holding the floor's
!>   components at v_g's (zero), a = g but zero in the held components, and the booked
!>   transfer loss equals sum_p m_p (v0 - v_x) . (v0 + v_new) / 2 (v_x = sum_i N_ip xpic_i),
!>   which differs from the change of the FLIP velocity's kinetic energy because the held
!>   components make the accelerations uneven;
!> - the higher the order, the more of the kinetic energy is kept (PIC keeps least, FLIP
!>   all), and none of the orders keeps the checkerboard: each keeps less than 1/4 of the
!>   start's kinetic energy, of which the checkerboard holds about 90 %.
program test_xpic
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, finish
    use mpm_error, only: error_type
    use mpm_strings, only: int_text
    use mpm_case, only: case_type, read_case_string, case_summary
    use mpm_solver, only: simulation_type, new_simulation, advance, start_energy_balance
    implicit none

    real(wp), parameter :: dx = 0.1_wp, dt = 1.0e-5_wp
    type(test_suite_type) :: suite
    real(wp), allocatable :: v0(:, :), expected(:, :), got(:, :), pic(:, :)
    real(wp), allocatable :: start_x(:, :), masses(:)
        !! start positions and masses of the particles of the last one_step
    real(wp) :: a_matrix(32, 32), loss, kinetic0, kinetic, kept(4)
    integer :: m, k
    integer, parameter :: orders(4) = [1, 2, 3, 6]

    call new_suite(suite, "xpic")
    call check_reading()
    call one_step('"transfer": "xpic", "xpic_order": 1', .false., v0, got, loss, kinetic0, &
        kinetic)
    if (size(got, 2) /= 32) then
        call check(suite, .false., "the block has 32 particles")
        call finish(suite)
    end if
    call build_a(a_matrix)
    call one_step('"transfer": "flip", "flip_fraction": 0', .false., v0, pic, loss, kinetic0, &
        kinetic)
    call one_step('"transfer": "xpic", "xpic_order": 1', .false., v0, got, loss, kinetic0, &
        kinetic)
    call check(suite, maxval(abs(got - pic)) <= 1.0e-12_wp*maxval(abs(v0)), &
        "XPIC(1) is PIC")
    do k = 1, 4
        m = orders(k)
        call one_step('"transfer": "xpic", "xpic_order": '//int_text(m), .false., v0, got, &
            loss, kinetic0, kinetic)
        expected = closed_form(m)
        call check(suite, maxval(abs(got - expected)) <= 1.0e-12_wp*maxval(abs(v0)), &
            "XPIC("//int_text(m)//"): v = [I - (I - A)^m] v0")
        call check(suite, abs(loss - (kinetic0 - kinetic)) <= 1.0e-12_wp*kinetic0 .and. &
            loss > 0.0_wp, "XPIC("//int_text(m)//"): the kinetic energy removed is booked")
        print "(a,i0,2(a,es10.3))", "XPIC(", m, "): largest error ", &
            maxval(abs(got - expected)), ", kinetic energy kept ", kinetic/kinetic0
        kept(k) = kinetic/kinetic0
        call one_step('"transfer": "xpic", "xpic_order": '//int_text(m), .true., v0, got, &
            loss, kinetic0, kinetic)
        call check(suite, maxval(abs(got - v0)) <= 1.0e-13_wp .and. &
            abs(loss) <= 1.0e-13_wp*kinetic0, "XPIC("//int_text(m)//"): a uniform velocity is kept")
    end do
    call check(suite, all(kept(2:) > kept(:3)) .and. kept(4) < 0.25_wp, &
        "a higher order keeps more kinetic energy, none keeps the checkerboard")
    do m = 1, 3
        call check_floor(m)
    end do
    call finish(suite)

contains

    !> "xpic" without an order is XPIC(2), and --check says so.
    subroutine check_reading()
        type(case_type) :: case
        type(error_type), allocatable :: error

        call read_case_string('{"domain": {"nx": 2, "ny": 2, "dx": 0.5}, "materials": '// &
            '[{"name": "m", "type": "linear_elastic", "E": 1e6, "nu": 0.3, "rho": 1000}], '// &
            '"bodies": [{"material": "m", "min": [0, 0], "max": [1, 1]}], "solver": '// &
            '{"transfer": "XPIC"}, "time": {"tend": 0.1}}', case, error, "read")
        call check(suite, .not. allocated(error), "xpic: valid")
        if (allocated(error)) return
        call check(suite, case%solver%xpic .and. .not. case%solver%apic .and. &
            case%solver%xpic_order == 2, "xpic: order 2 by default")
        call check(suite, index(case_summary(case), ", XPIC(2) transfer") > 0, "xpic: summary")
    end subroutine check_reading

    !> XPIC(m) with gravity on a sliding floor against the closed form with held components.
    subroutine check_floor(m)
        integer, intent(in) :: m
            !! the order

        real(wp), parameter :: g = -10.0_wp
        real(wp), allocatable :: w(:, :), node_mass(:), vg(:, :), u(:, :), total(:, :), &
            acc(:, :), vx(:, :), vnew(:, :), wp_u(:, :)
        logical, allocatable :: held(:)
        real(wp) :: coefficient, expected_loss, flip_loss
        integer :: n, i, k, ix, iy, p, c
        character(len=:), allocatable :: label

        label = int_text(m)
        call one_step('"transfer": "xpic", "xpic_order": '//label, .false., v0, got, loss, &
            kinetic0, kinetic, floor=.true.)
        n = size(masses)
        if (n == 0) return
        ! the bilinear weights of the 7 x 5 nodes (node i = 1 + ix + 7 iy)
        allocate (w(35, n), node_mass(35), held(35))
        do p = 1, n
            do iy = 0, 4
                do ix = 0, 6
                    w(1 + ix + 7*iy, p) = max(0.0_wp, 1 - abs(start_x(1, p)/dx - ix)) &
                        *max(0.0_wp, 1 - abs(start_x(2, p)/dx - iy))
                end do
            end do
        end do
        node_mass = matmul(w, masses)
        held = [(i <= 7, i = 1, 35)]
        ! v_g and the accelerations, the floor's v_y held
        allocate (vg(2, 35), acc(2, 35))
        do c = 1, 2
            vg(c, :) = matmul(w, masses*v0(c, :))/max(node_mass, tiny(1.0_wp))
        end do
        acc(1, :) = 0.0_wp
        acc(2, :) = g
        where (node_mass <= 0.0_wp)
            acc(2, :) = 0.0_wp
        end where
        where (held)
            vg(2, :) = 0.0_wp
            acc(2, :) = 0.0_wp
        end where
        u = vg
        coefficient = real(m, wp)
        total = coefficient*u
        do k = 2, m
            wp_u = matmul(u, w)
            do c = 1, 2
                u(c, :) = matmul(w, masses*wp_u(c, :))/max(node_mass, tiny(1.0_wp))
            end do
            where (held) u(2, :) = 0.0_wp
            coefficient = -coefficient*real(m - k + 1, wp)/real(k, wp)
            total = total + coefficient*u
        end do
        vx = matmul(total, w)
        vnew = matmul(total + dt*acc, w)
        call check(suite, maxval(abs(got - vnew)) <= 1.0e-12_wp*maxval(abs(v0)), &
            "floor, XPIC("//label//"): v = sum N (xpic + dt a) with the held components")
        expected_loss = 0.5_wp*sum(spread(masses, 1, 2)*(v0 - vx)*(v0 + vnew))
        flip_loss = 0.5_wp*sum(spread(masses, 1, 2)*((v0 + matmul(dt*acc, w))**2 - vnew**2))
        call check(suite, abs(loss - expected_loss) <= 1.0e-12_wp*kinetic0 .and. &
            abs(expected_loss - flip_loss) > 1.0e-9_wp*kinetic0, "floor, XPIC("//label// &
            "): the loss is the removed velocity at the mean velocity of the step")
        print "(a,i0,3(a,es10.3))", "floor XPIC(", m, "): largest error ", &
            maxval(abs(got - vnew)), ", loss error ", loss - expected_loss, &
            ", against the FLIP-energy form ", expected_loss - flip_loss
    end subroutine check_floor

    !> One MUSL step of the block with the solver keys `transfer`; the velocities before
    !> (v0, dim x n) and after, the transfer loss and the kinetic energies. With `floor` the
    !> block rests on a sliding floor (y from 0) under gravity -10 m/s2.
    subroutine one_step(transfer, uniform, v0, v, loss, kinetic0, kinetic, floor)
        character(len=*), intent(in) :: transfer
            !! solver keys
        logical, intent(in) :: uniform
            !! start from a uniform velocity instead of the mixed field
        real(wp), allocatable, intent(out) :: v0(:, :), v(:, :)
        real(wp), intent(out) :: loss, kinetic0, kinetic
        logical, intent(in), optional :: floor

        type(case_type) :: case
        character(len=:), allocatable :: place
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        integer :: p, i, j

        allocate (v0(2, 0), v(2, 0))
        loss = 0.0_wp
        kinetic0 = 1.0_wp
        kinetic = 1.0_wp
        place = '"domain": {"nx": 6, "ny": 4, "dx": 0.1}, "bodies": [{"material": "m", '// &
            '"min": [0.1, 0.1], "max": [0.5, 0.3]}], "gravity": [0, 0], '
        if (present(floor)) then
            if (floor) place = '"domain": {"nx": 6, "ny": 4, "dx": 0.1, "boundaries": '// &
                '{"ymin": "sliding"}}, "bodies": [{"material": "m", "min": [0.1, 0.0], '// &
                '"max": [0.5, 0.2]}], "gravity": [0, -10], '
        end if
        call read_case_string('{"name": "xpic", '//place// &
            '"particles": {"ppc": 2}, "materials": [{"name": "m", "type": "linear_elastic", '// &
            '"E": 1e6, "nu": 0.3, "rho": 1000}], "solver": {"scheme": '// &
            '"MUSL", "shape_function": "linear", '//transfer//'}, "time": {"tend": 1, '// &
            '"dt": 1e-5}}', case, error, "xpic")
        call check(suite, .not. allocated(error), transfer//": case is valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call new_simulation(sim, case, error)
        if (allocated(error)) return
        do p = 1, sim%particles%n
            i = nint((sim%particles%x(1, p) - 0.1_wp)/(0.5_wp*dx) - 0.5_wp)
            j = nint(sim%particles%x(2, p)/(0.5_wp*dx) - 0.5_wp)
            if (uniform) then
                sim%particles%v(:, p) = [0.1_wp, -0.05_wp]
            else
                sim%particles%v(:, p) = [0.1_wp + 0.02_wp*sim%particles%x(2, p)/dx &
                    + 0.3_wp*(-1)**(i + j), -0.05_wp + 0.2_wp*(-1)**i]
            end if
        end do
        call start_energy_balance(sim)
        v0 = sim%particles%v
        start_x = sim%particles%x
        masses = sim%particles%mass
        kinetic0 = sim%energy%kinetic
        call advance(sim, dt, error)
        call check(suite, .not. allocated(error), transfer//": the step runs")
        if (allocated(error)) return
        v = sim%particles%v
        loss = sim%energy%transfer
        kinetic = sim%energy%kinetic
    end subroutine one_step

    !> A_pq = sum_i w_ip w_iq m_q / m_i with the bilinear weights of the particles' start
    !> positions (positions, masses of the last one_step).
    subroutine build_a(a)
        real(wp), intent(out) :: a(:, :)

        real(wp) :: w(7, 5, size(masses)), node_mass(7, 5)
        integer :: p, q, ix, iy

        do p = 1, size(masses)
            do iy = 1, 5
                do ix = 1, 7
                    w(ix, iy, p) = max(0.0_wp, 1 - abs(start_x(1, p)/dx - (ix - 1))) &
                        *max(0.0_wp, 1 - abs(start_x(2, p)/dx - (iy - 1)))
                end do
            end do
        end do
        node_mass = 0.0_wp
        do p = 1, size(masses)
            node_mass = node_mass + masses(p)*w(:, :, p)
        end do
        do q = 1, size(masses)
            do p = 1, size(masses)
                a(p, q) = sum(w(:, :, p)*w(:, :, q)*masses(q)/max(node_mass, tiny(1.0_wp)))
            end do
        end do
    end subroutine build_a

    !> [I - (I - A)^m] v0, each component.
    function closed_form(m) result(v)
        integer, intent(in) :: m
        real(wp), allocatable :: v(:, :)

        real(wp) :: residual(size(v0, 2))
        integer :: c, k

        allocate (v(size(v0, 1), size(v0, 2)))
        do c = 1, size(v0, 1)
            residual = v0(c, :)
            do k = 1, m
                residual = residual - matmul(a_matrix, residual)
            end do
            v(c, :) = v0(c, :) - residual
        end do
    end function closed_form

end program test_xpic
