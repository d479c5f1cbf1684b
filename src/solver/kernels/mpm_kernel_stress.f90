!> The stress of a block of particles: the kernel of the stress pass (mpm_transfer). For the
!> velocity-gradient increments of a block of particles it hands the strain increments and
!> spins to the materials, updates F and the volume, and sums the work of
!> the stresses and the stored elastic energy by work kind. It sees the particle arrays it
!> works on, the laws and the block: no particles_type, grid, case, I/O or coarrays.
module mpm_kernel_stress
    use mpm_kinds, only: wp
    use mpm_material, only: material_holder_type, nwork_kinds
    implicit none
    private
    public :: stress_block, determinant, gather_block, nstress_sums

    integer, parameter :: nstress_sums = 2*nwork_kinds
        !! sums of a stress pass: the work of the stresses over the step by work kind of the
        !! materials (1 : nwork_kinds, `work_*` of mpm_material), then the elastic energy
        !! stored in the particles at the end of the step by work kind [J]

    integer, parameter :: gather_block = 256
        !! particles per block of the passes that only gather (load balance; the partial sums
        !! of a block are added in block order)

contains

    !> The stress update of the particles `order` (a block of at most gather_block) for the
    !> increments ldt(:, :, j) = dt L of their velocity gradients (ldt(i, k) =
    !> dt d v_i / d x_k, particle order(j)): strain increments D dt and spins W dt to
    !> the materials, one call per run of particles of the same material (update_stress_block:
    !> no call per particle for the simple ones), then F <- (I + ldt) F, V = det(F) V0 (the
    !> cpGIMP domain follows from F where it is needed: mpm_particle_domain::domain_half_sizes); adds
    !> the work of the stresses over the step and the elastic energy the particles store at
    !> its end to `work` (by work kind of the materials, see nstress_sums), particle by
    !> particle in order. A kernel: it sees the particle arrays
    !> it works on, the laws and the block, no particles_type, grid, case, I/O or coarrays.
    subroutine stress_block(order, material, stress, state, f, volume, volume0, materials, &
            ldt, dt, dim, work, strain)
        integer, intent(in) :: order(:)
            !! the block's particles, in order (at most gather_block)
        integer, intent(in) :: material(:)
            !! material of each particle (all particles)
        real(wp), contiguous, intent(inout) :: stress(:, :)
            !! Cauchy stress (nstress, all particles) [Pa]
        real(wp), contiguous, intent(inout) :: state(:, :)
            !! material state (nstate, all particles) [-]
        real(wp), contiguous, intent(inout) :: f(:, :, :)
            !! deformation gradient (dim, dim, all particles) [-]
        real(wp), intent(inout) :: volume(:)
            !! current volume (all particles) [m3]
        real(wp), intent(in) :: volume0(:)
            !! initial volume (all particles) [m3]
        type(material_holder_type), intent(in) :: materials(:)
            !! materials of the case
        real(wp), intent(in) :: ldt(3, 3, gather_block)
            !! dt times the velocity gradients (first dim rows and columns) [-]
        real(wp), intent(in) :: dt
            !! time step [s]
        integer, intent(in) :: dim
            !! space dimensions
        real(wp), intent(inout) :: work(nstress_sums)
            !! sums of (V sigma)_mid : d_eps, then of the stored elastic energy V w(sigma),
            !! by work kind [J]
        real(wp), contiguous, intent(inout), optional :: strain(:, :)
            !! accumulated strain (nstress, all particles), when it is held [-]

        integer :: n, ns, nstate, j, j0, j1, p, a, mat
        integer :: kind(gather_block)
        real(wp) :: s(6, gather_block), sold(6, gather_block), de(6, gather_block), &
            om(3, gather_block), vold, jac, density(gather_block), w
        real(wp) :: st(size(state, 1), size(order))

        n = size(order)
        ns = size(stress, 1)
        nstate = size(state, 1)
        do j = 1, n
            p = order(j)
            de(1, j) = ldt(1, 1, j)
            de(2, j) = ldt(2, 2, j)
            de(4, j) = 0.5_wp*(ldt(1, 2, j) + ldt(2, 1, j))
            om(1, j) = 0.5_wp*(ldt(1, 2, j) - ldt(2, 1, j))
            if (dim == 3) then
                de(3, j) = ldt(3, 3, j)
                de(5, j) = 0.5_wp*(ldt(2, 3, j) + ldt(3, 2, j))
                de(6, j) = 0.5_wp*(ldt(3, 1, j) + ldt(1, 3, j))
                om(2, j) = 0.5_wp*(ldt(2, 3, j) - ldt(3, 2, j))
                om(3, j) = 0.5_wp*(ldt(3, 1, j) - ldt(1, 3, j))
            else
                de(3, j) = 0.0_wp
                om(2:3, j) = 0.0_wp
            end if
            ! copies of a size known here: a runtime-sized copy is a memcpy call per particle
            if (ns == 4) then
                s(1:4, j) = stress(1:4, p)
            else
                s(1:6, j) = stress(1:6, p)
            end if
            sold(:, j) = s(:, j)
            if (nstate > 0) st(:, j) = state(:, p)
        end do
        ! runs of particles of one material
        j0 = 1
        do while (j0 <= n)
            mat = material(order(j0))
            j1 = j0
            do while (j1 < n)
                if (material(order(j1 + 1)) /= mat) exit
                j1 = j1 + 1
            end do
            call materials(mat)%m%update_stress_block(j1 - j0 + 1, s(1:ns, j0:j1), &
                de(1:ns, j0:j1), om(:, j0:j1), dt, st(:, j0:j1))
            call materials(mat)%m%elastic_energy_block(j1 - j0 + 1, s(1:ns, j0:j1), &
                st(:, j0:j1), density(j0:j1))
            kind(j0:j1) = materials(mat)%m%work_kind()
            j0 = j1 + 1
        end do
        do j = 1, n
            p = order(j)
            if (ns == 4) then
                stress(1:4, p) = s(1:4, j)
            else
                stress(1:6, p) = s(1:6, j)
            end if
            if (nstate > 0) state(:, p) = st(:, j)
            if (present(strain)) then
                strain(:, p) = strain(:, p) + de(1:ns, j)
            end if
            ! deformation gradient F <- (I + ldt) F and volume
            if (dim == 2) then
                call deform_2d(f(:, :, p), ldt(:, :, j), jac)
            else
                call deform_3d(f(:, :, p), ldt(:, :, j), jac)
            end if
            vold = volume(p)
            volume(p) = jac*volume0(p)
            ! trapezoidal rule on V sigma (volume and stress at both ends of the step):
            ! second order in dt, also when the volume changes with the strain
            ! (V sigma)_mid : de, shear components twice (tensor components)
            w = 0.0_wp
            do a = 1, 3
                w = w + 0.5_wp*(vold*sold(a, j) + volume(p)*s(a, j))*de(a, j)
            end do
            do a = 4, ns
                w = w + (vold*sold(a, j) + volume(p)*s(a, j))*de(a, j)
            end do
            work(kind(j)) = work(kind(j)) + w
            work(nwork_kinds + kind(j)) = work(nwork_kinds + kind(j)) &
                + density(j)*volume(p)
        end do
    end subroutine stress_block

    !> F <- (I + ldt) F in 2D and its determinant.
    pure subroutine deform_2d(f, ldt, jac)
        real(wp), intent(inout) :: f(2, 2)
            !! deformation gradient
        real(wp), intent(in) :: ldt(3, 3)
            !! dt times the velocity gradient
        real(wp), intent(out) :: jac
            !! det F
        real(wp) :: g(2, 2)
        integer :: b

        do b = 1, 2
            g(1, b) = f(1, b) + ldt(1, 1)*f(1, b) + ldt(1, 2)*f(2, b)
            g(2, b) = f(2, b) + ldt(2, 1)*f(1, b) + ldt(2, 2)*f(2, b)
        end do
        jac = g(1, 1)*g(2, 2) - g(1, 2)*g(2, 1)
        f = g
    end subroutine deform_2d

    !> F <- (I + ldt) F in 3D and its determinant.
    pure subroutine deform_3d(f, ldt, jac)
        real(wp), intent(inout) :: f(3, 3)
            !! deformation gradient
        real(wp), intent(in) :: ldt(3, 3)
            !! dt times the velocity gradient
        real(wp), intent(out) :: jac
            !! det F
        real(wp) :: g(3, 3)
        integer :: a, b

        do b = 1, 3
            do a = 1, 3
                g(a, b) = f(a, b) + ldt(a, 1)*f(1, b) + ldt(a, 2)*f(2, b) + ldt(a, 3)*f(3, b)
            end do
        end do
        jac = determinant(g, 3)
        f = g
    end subroutine deform_3d

    !> Determinant of a 2x2 or 3x3 matrix.
    pure real(wp) function determinant(m, dim)
        real(wp), intent(in) :: m(:, :)
        integer, intent(in) :: dim
        if (dim == 2) then
            determinant = m(1, 1)*m(2, 2) - m(1, 2)*m(2, 1)
        else
            determinant = m(1, 1)*(m(2, 2)*m(3, 3) - m(2, 3)*m(3, 2)) &
                - m(1, 2)*(m(2, 1)*m(3, 3) - m(2, 3)*m(3, 1)) &
                + m(1, 3)*(m(2, 1)*m(3, 2) - m(2, 2)*m(3, 1))
        end if
    end function determinant

end module mpm_kernel_stress
